// LLVM IR emission over the code plan and the ORC LLJIT backend. Each plan
// node becomes one instruction (or a short sequence) computed once; domain
// errors are i1 bits carried alongside values exactly as the interpreter
// does; functions over chunkSize nodes are split into non-inlined helpers
// that pass values through a scratch array, so O2 and instruction selection
// see bounded functions and compile time grows linearly with model size.
// Built into the JIT module, libldae_jit.so (JitBackend.h).
#include "codegen/LlvmEmitter.h"

#include "codegen/ObjectCache.h"

#include "llvm/ExecutionEngine/Orc/CompileUtils.h"
#include "llvm/ExecutionEngine/Orc/ExecutionUtils.h"
#include "llvm/ExecutionEngine/Orc/JITTargetMachineBuilder.h"
#include "llvm/ExecutionEngine/Orc/LLJIT.h"
#include "llvm/ExecutionEngine/Orc/ThreadSafeModule.h"
#include "llvm/IR/IRBuilder.h"
#include "llvm/IR/Intrinsics.h"
#include "llvm/IR/LLVMContext.h"
#include "llvm/IR/Module.h"
#include "llvm/IR/Verifier.h"
#include "llvm/Passes/PassBuilder.h"
#include "llvm/Support/CommandLine.h"
#include "llvm/Support/ErrorHandling.h"
#include "llvm/Support/TargetSelect.h"
#include "llvm/Support/raw_ostream.h"
#include "llvm/Target/TargetMachine.h"

#include <cmath>
#include <mutex>
#include <unistd.h>

namespace ldae::codegen {

using ir::CompareKind;
using ir::FuncKind;

namespace {

/// Scratch arrays up to this many bytes live on the stack; larger ones are
/// allocated with malloc.
constexpr uint64_t kMaxStackScratch = 64 * 1024;

/// Emits the body of one chunk of a plan function into the current block.
class ChunkEmitter {
public:
  /// Arguments of the chunk: t, y, yp, p, cj, out0, out1, tmp (any may be
  /// null when the signature lacks it).
  struct Args {
    llvm::Value *t, *y, *yp, *p, *cj, *out0, *out1, *tmp;
  };

  /// `columns` (a loop body's): the i64 value of each index column in the
  /// current iteration; load and store indices then name columns. `rcIn`:
  /// the return code so far (0 when null).
  ChunkEmitter(llvm::IRBuilder<> &b, llvm::Module &m, const PlanFunction &fn,
               const PlanChunk &chunk, Args args,
               const std::vector<llvm::Value *> *columns = nullptr,
               llvm::Value *rcIn = nullptr)
      : b_(b), m_(m), fn_(fn), chunk_(chunk), args_(args), columns_(columns),
        rcIn_(rcIn), dbl_(b.getDoubleTy()), val_(fn.nodes.size(), nullptr),
        err_(fn.nodes.size(), nullptr) {}

  /// The functions Reduce nodes call (emitReduction), by reduction index.
  void setReductions(const std::vector<llvm::Function *> *r) {
    reductions_ = r;
  }
  /// Value and error bit (i1) of node k after emit().
  llvm::Value *result(uint32_t k) { return value(k); }
  llvm::Value *resultError(uint32_t k) { return error(k); }

  /// Emits nodes and stores; returns the i32 return code.
  llvm::Value *emit() {
    rc_ = rcIn_ ? rcIn_ : b_.getInt32(0);
    uint32_t next = chunk_.storeBegin;
    for (uint32_t k = chunk_.nodeBegin; k < chunk_.nodeEnd; ++k) {
      const PlanNode &n = fn_.nodes[k];
      if (!isLeaf(n.op)) {
        computeNode(k);
        if (fn_.spill[k] >= 0) {
          b_.CreateStore(val_[k], slot(fn_.spill[k]));
          if (n.mayFail)
            b_.CreateStore(boolean(err_[k]),
                           slot(fn_.spill[k] + 1));
        }
      }
      for (; next < chunk_.storeEnd && fn_.stores[next].after <= k; ++next)
        store(fn_.stores[next]);
    }
    for (; next < chunk_.storeEnd; ++next)
      store(fn_.stores[next]);
    return rc_;
  }

private:
  /// Writes a store's value; a set error bit makes it the return code
  /// unless an earlier store already failed.
  void store(const PlanStore &s) {
    llvm::Value *out = s.array ? args_.out1 : args_.out0;
    b_.CreateStore(value(s.node), address(out, s.index));
    if (fn_.nodes[s.node].mayFail) {
      llvm::Value *first =
          b_.CreateAnd(b_.CreateICmpEQ(rc_, b_.getInt32(0)), error(s.node));
      llvm::Value *row =
          columns_ ? b_.CreateAdd(b_.CreateTrunc((*columns_)[s.row],
                                                 b_.getInt32Ty()),
                                  b_.getInt32(1))
                   : b_.getInt32(s.row + 1);
      rc_ = b_.CreateSelect(first, row, rc_);
    }
  }

  /// &base[index]; in a loop body `index` names a column.
  llvm::Value *address(llvm::Value *base, int64_t index) {
    if (columns_)
      return b_.CreateInBoundsGEP(dbl_, base, (*columns_)[index]);
    return b_.CreateConstInBoundsGEP1_64(dbl_, base, index);
  }

  bool inChunk(uint32_t k) const {
    return k >= chunk_.nodeBegin && k < chunk_.nodeEnd;
  }
  llvm::Value *slot(int32_t i) {
    return b_.CreateConstInBoundsGEP1_64(dbl_, args_.tmp, i);
  }
  /// Inputs never change during a call: invariant, dereferenceable loads
  /// need no ordering against stores (keeps instruction scheduling cheap).
  llvm::Value *load(llvm::Value *base, int64_t i) {
    llvm::LoadInst *l = b_.CreateLoad(dbl_, address(base, i));
    l->setMetadata(llvm::LLVMContext::MD_invariant_load,
                   llvm::MDNode::get(b_.getContext(), {}));
    return l;
  }

  /// The value of node k here: leaves re-materialized, earlier chunks'
  /// values loaded from the scratch array.
  llvm::Value *value(uint32_t k) {
    if (val_[k])
      return val_[k];
    const PlanNode &n = fn_.nodes[k];
    llvm::Value *v = nullptr;
    switch (n.op) {
    case OpCode::Const: v = llvm::ConstantFP::get(dbl_, n.value); break;
    case OpCode::LoadY: v = load(args_.y, n.index); break;
    case OpCode::LoadYp: v = load(args_.yp, n.index); break;
    case OpCode::LoadP: v = load(args_.p, n.index); break;
    case OpCode::Time: v = args_.t; break;
    case OpCode::Cj: v = args_.cj; break;
    default:
      assert(!inChunk(k) && fn_.spill[k] >= 0 && "value used before defined");
      v = b_.CreateLoad(dbl_, slot(fn_.spill[k]));
    }
    return val_[k] = v;
  }
  llvm::Value *error(uint32_t k) {
    if (!fn_.nodes[k].mayFail)
      return b_.getFalse();
    if (err_[k])
      return err_[k];
    assert(!inChunk(k) && fn_.spill[k] >= 0);
    return err_[k] = b_.CreateFCmpUNE(
               b_.CreateLoad(dbl_, slot(fn_.spill[k] + 1)),
               llvm::ConstantFP::get(dbl_, 0.0));
  }

  llvm::Value *intrinsic(llvm::Intrinsic::ID id, llvm::Value *a) {
    return b_.CreateUnaryIntrinsic(id, a);
  }
  llvm::Value *libm(const char *name, llvm::ArrayRef<llvm::Value *> args) {
    std::vector<llvm::Type *> types(args.size(), dbl_);
    llvm::FunctionCallee f =
        m_.getOrInsertFunction(name, llvm::FunctionType::get(dbl_, types, false));
    return b_.CreateCall(f, args);
  }
  llvm::Value *zero() { return llvm::ConstantFP::get(dbl_, 0.0); }
  llvm::Value *one() { return llvm::ConstantFP::get(dbl_, 1.0); }
  /// 1.0 or 0.0. Through i32 and a signed conversion: x86's FastISel has
  /// no unsigned one (short of AVX-512) and hands the rest of the block to
  /// SelectionDAG, 30x slower (a 160k-operation SGA Jacobian: 10 s).
  llvm::Value *boolean(llvm::Value *i1) {
    return b_.CreateSIToFP(b_.CreateZExt(i1, b_.getInt32Ty()), dbl_);
  }
  llvm::Value *truth(llvm::Value *v) { return b_.CreateFCmpUNE(v, zero()); }

  void computeNode(uint32_t k) {
    const PlanNode &n = fn_.nodes[k];
    llvm::Value *a = value(n.a);
    llvm::Value *b = numOperands(n.op) >= 2 ? value(n.b) : nullptr;
    llvm::Value *r = nullptr, *check = nullptr;
    switch (n.op) {
    case OpCode::Add: r = b_.CreateFAdd(a, b); break;
    case OpCode::Sub: r = b_.CreateFSub(a, b); break;
    case OpCode::Mul: r = b_.CreateFMul(a, b); break;
    case OpCode::Div:
      r = b_.CreateFDiv(a, b);
      check = b_.CreateFCmpOEQ(b, zero());
      break;
    case OpCode::Neg: r = b_.CreateFNeg(a); break;
    case OpCode::PowInt: {
      llvm::Value *base = a;
      for (PowIntStep s : powIntSteps(n.index)) {
        if (s.multiplyResult)
          r = r ? b_.CreateFMul(r, base) : base;
        if (s.squareBase)
          base = b_.CreateFMul(base, base);
      }
      break;
    }
    case OpCode::Pow:
      r = b_.CreateBinaryIntrinsic(llvm::Intrinsic::pow, a, b);
      check = b_.CreateOr(
          b_.CreateAnd(b_.CreateFCmpOLT(a, zero()),
                       b_.CreateFCmpUNE(
                           intrinsic(llvm::Intrinsic::floor, b), b)),
          b_.CreateAnd(b_.CreateFCmpOEQ(a, zero()),
                       b_.CreateFCmpOLT(b, zero())));
      break;
    case OpCode::Sqrt:
      r = intrinsic(llvm::Intrinsic::sqrt, a);
      check = b_.CreateFCmpOLT(a, zero());
      break;
    case OpCode::Func1:
      r = unary(FuncKind(n.sub), a, check);
      break;
    case OpCode::Func2:
      switch (FuncKind(n.sub)) {
      case FuncKind::Atan2: r = libm(cMathName(FuncKind::Atan2), {a, b}); break;
      case FuncKind::Min: r = b_.CreateSelect(b_.CreateFCmpOLT(a, b), a, b); break;
      case FuncKind::Max: r = b_.CreateSelect(b_.CreateFCmpOGT(a, b), a, b); break;
      case FuncKind::Mod:
        r = b_.CreateFSub(
            a, b_.CreateFMul(intrinsic(llvm::Intrinsic::floor,
                                       b_.CreateFDiv(a, b)),
                             b));
        check = b_.CreateFCmpOEQ(b, zero());
        break;
      default: assert(false && "not a binary built-in");
      }
      break;
    case OpCode::Select: {
      llvm::Value *c = truth(a);
      r = b_.CreateSelect(c, b, value(n.c));
      if (n.mayFail)
        err_[k] = b_.CreateOr(error(n.a),
                              b_.CreateSelect(c, error(n.b), error(n.c)));
      break;
    }
    case OpCode::Compare: {
      static const llvm::CmpInst::Predicate preds[] = {
          llvm::CmpInst::FCMP_OLT, llvm::CmpInst::FCMP_OLE,
          llvm::CmpInst::FCMP_OGT, llvm::CmpInst::FCMP_OGE,
          llvm::CmpInst::FCMP_OEQ, llvm::CmpInst::FCMP_UNE};
      r = boolean(b_.CreateFCmp(preds[n.sub], a, b));
      break;
    }
    case OpCode::And:
    case OpCode::Or: {
      llvm::Value *ta = truth(a);
      bool isAnd = n.op == OpCode::And;
      r = boolean(isAnd ? b_.CreateAnd(ta, truth(b)) : b_.CreateOr(ta, truth(b)));
      if (n.mayFail) // b's error matters only when a does not decide
        err_[k] = b_.CreateOr(
            error(n.a),
            b_.CreateAnd(isAnd ? ta : b_.CreateNot(ta), error(n.b)));
      break;
    }
    case OpCode::Not: r = boolean(b_.CreateFCmpOEQ(a, zero())); break;
    case OpCode::ExtArg: r = a; break;
    case OpCode::ExtCall: {
      if (n.sub != 1) {
        r = externalCall(k);
        check = b_.CreateFCmpUNO(r, r);
        break;
      }
      // Only where the guard holds (a branch of an if taken): tables keep
      // state between calls.
      llvm::BasicBlock *before = b_.GetInsertBlock();
      llvm::Function *f = before->getParent();
      auto *call = llvm::BasicBlock::Create(b_.getContext(), "ext.call", f);
      auto *done = llvm::BasicBlock::Create(b_.getContext(), "ext.done", f);
      b_.CreateCondBr(truth(b), call, done);
      b_.SetInsertPoint(call);
      llvm::Value *called = externalCall(k);
      llvm::BasicBlock *callEnd = b_.GetInsertBlock();
      b_.CreateBr(done);
      b_.SetInsertPoint(done);
      llvm::PHINode *phi = b_.CreatePHI(dbl_, 2);
      phi->addIncoming(zero(), before);
      phi->addIncoming(called, callEnd);
      r = phi;
      check = b_.CreateFCmpUNO(r, r);
      break;
    }
    case OpCode::Reduce: {
      llvm::Value *slot = nullptr;
      if (n.mayFail)
        slot = b_.CreateAlloca(b_.getInt32Ty());
      r = b_.CreateCall((*reductions_)[n.index],
                        {args_.t, args_.y, args_.yp, args_.p, args_.cj, a,
                         slot ? slot
                              : llvm::ConstantPointerNull::get(b_.getPtrTy())});
      if (n.mayFail)
        err_[k] = b_.CreateOr(
            error(n.a),
            b_.CreateICmpNE(b_.CreateLoad(b_.getInt32Ty(), slot),
                            b_.getInt32(0)));
      break;
    }
    default: assert(false && "leaf in computeNode");
    }
    val_[k] = r;
    if (n.mayFail && !err_[k]) {
      llvm::Value *e = check ? check : b_.getFalse();
      for (unsigned i = 0; i < numOperands(n.op); ++i)
        if (fn_.nodes[n.operand(i)].mayFail)
          e = b_.CreateOr(e, error(n.operand(i)));
      err_[k] = e;
    }
  }

  /// `void symbol(const double *in, double *out)` on stack arrays.
  llvm::Value *externalCall(uint32_t k) {
    const PlanNode &n = fn_.nodes[k];
    const PlanExternal &x = fn_.externals[n.index];
    std::vector<uint32_t> args = externalArguments(fn_.nodes, k);
    auto *inTy = llvm::ArrayType::get(dbl_, std::max<size_t>(1, args.size()));
    auto *outTy = llvm::ArrayType::get(dbl_, std::max(1u, x.numOutputs));
    llvm::Value *in = b_.CreateAlloca(inTy);
    llvm::Value *out = b_.CreateAlloca(outTy);
    for (size_t i = 0; i < args.size(); ++i)
      b_.CreateStore(value(args[i]),
                     b_.CreateConstInBoundsGEP2_32(inTy, in, 0, unsigned(i)));
    llvm::FunctionCallee f = m_.getOrInsertFunction(
        x.symbol, llvm::FunctionType::get(b_.getVoidTy(),
                                          {b_.getPtrTy(), b_.getPtrTy()},
                                          false));
    b_.CreateCall(f, {in, out});
    return b_.CreateLoad(
        dbl_, b_.CreateConstInBoundsGEP2_32(outTy, out, 0, unsigned(n.value)));
  }

  llvm::Value *unary(FuncKind f, llvm::Value *a, llvm::Value *&check) {
    using llvm::Intrinsic::ID;
    switch (f) {
    case FuncKind::Sin: return intrinsic(llvm::Intrinsic::sin, a);
    case FuncKind::Cos: return intrinsic(llvm::Intrinsic::cos, a);
    case FuncKind::Exp: return intrinsic(llvm::Intrinsic::exp, a);
    case FuncKind::Log:
    case FuncKind::Log10:
      check = b_.CreateFCmpULE(a, zero()); // !(a > 0)
      return intrinsic(f == FuncKind::Log ? llvm::Intrinsic::log
                                          : llvm::Intrinsic::log10,
                       a);
    case FuncKind::Sqrt: return intrinsic(llvm::Intrinsic::sqrt, a);
    case FuncKind::Abs: return intrinsic(llvm::Intrinsic::fabs, a);
    case FuncKind::Floor: return intrinsic(llvm::Intrinsic::floor, a);
    case FuncKind::Ceil: return intrinsic(llvm::Intrinsic::ceil, a);
    case FuncKind::Sign:
      return b_.CreateFSub(boolean(b_.CreateFCmpOGT(a, zero())),
                           boolean(b_.CreateFCmpOLT(a, zero())));
    case FuncKind::Asin:
    case FuncKind::Acos:
      check = b_.CreateFCmpOGT(intrinsic(llvm::Intrinsic::fabs, a), one());
      return libm(cMathName(f), {a});
    default: // tan, atan, sinh, cosh, tanh: libm by name
      assert(cMathName(f) && "unary built-in without lowering");
      return libm(cMathName(f), {a});
    }
  }

  llvm::IRBuilder<> &b_;
  llvm::Module &m_;
  const PlanFunction &fn_;
  const PlanChunk &chunk_;
  Args args_;
  const std::vector<llvm::Value *> *columns_;
  llvm::Value *rcIn_;
  const std::vector<llvm::Function *> *reductions_ = nullptr;
  llvm::Type *dbl_;
  std::vector<llvm::Value *> val_, err_;
  llvm::Value *rc_ = nullptr;
};

/// Inputs are read-only, outputs write-only-by-us and unaliased (the ABI:
/// the runtime never passes overlapping arrays), so loads and stores can be
/// reordered freely; this also keeps instruction scheduling linear.
void setPointerAttributes(const CodePlan &plan, llvm::Function *f,
                          std::vector<unsigned> inputs,
                          std::vector<unsigned> outputs,
                          unsigned paramsArg = 3) {
  if (paramsArg != 3)
    inputs.push_back(paramsArg);
  for (unsigned i : inputs) {
    f->addParamAttr(i, llvm::Attribute::ReadOnly);
    f->addParamAttr(i, llvm::Attribute::NoCapture);
    uint64_t size = i == paramsArg ? plan.pSize() : plan.n;
    if (size)
      f->addDereferenceableParamAttr(i, size * 8);
  }
  for (unsigned i : outputs) {
    f->addParamAttr(i, llvm::Attribute::NoAlias);
    f->addParamAttr(i, llvm::Attribute::NoCapture);
  }
}

/// The counted loop of a PlanLoop in a fresh function: i from 0 to count - 1,
/// values carried from one iteration to the next as phis, and the index
/// columns computed at the top of each iteration.
class CountedLoop {
public:
  CountedLoop(llvm::IRBuilder<> &b, llvm::Module &m, const PlanLoop &loop,
              llvm::Function *f, llvm::ArrayRef<llvm::Value *> initial)
      : b_(b), count_(loop.count) {
    llvm::LLVMContext &ctx = m.getContext();
    b.SetInsertPoint(llvm::BasicBlock::Create(ctx, "entry", f));
    entry_ = b.GetInsertBlock();
    header_ = llvm::BasicBlock::Create(ctx, "loop", f);
    exit_ = llvm::BasicBlock::Create(ctx, "exit", f);
    b.CreateBr(header_);
    b.SetInsertPoint(header_);
    i_ = b.CreatePHI(b.getInt64Ty(), 2, "i");
    i_->addIncoming(b.getInt64(0), entry_);
    for (llvm::Value *v : initial) {
      carried_.push_back(b.CreatePHI(v->getType(), 2));
      carried_.back()->addIncoming(v, entry_);
    }
    for (size_t c = 0; c < loop.columns.size(); ++c) {
      const IndexColumn &col = loop.columns[c];
      if (col.affine()) {
        columns_.push_back(b.CreateAdd(
            b.getInt64(col.base),
            b.CreateMul(i_, b.getInt64(col.stride), "", false, true), "",
            false, true));
        continue;
      }
      auto *data = llvm::ConstantDataArray::get(
          ctx, llvm::ArrayRef<int32_t>(col.table));
      auto *table = new llvm::GlobalVariable(
          m, data->getType(), true, llvm::GlobalValue::PrivateLinkage, data,
          f->getName() + ".col" + std::to_string(c));
      llvm::Value *at = b.CreateLoad(
          b.getInt32Ty(),
          b.CreateInBoundsGEP(data->getType(), table, {b.getInt64(0), i_}));
      columns_.push_back(b.CreateSExt(at, b.getInt64Ty()));
    }
  }
  const std::vector<llvm::Value *> &columns() const { return columns_; }
  llvm::Value *carried(unsigned k) const { return carried_[k]; }
  /// Ends the iteration with the next carried values; leaves the builder
  /// in the exit block.
  void close(llvm::ArrayRef<llvm::Value *> next) {
    llvm::BasicBlock *latch = b_.GetInsertBlock();
    llvm::Value *i1 = b_.CreateAdd(i_, b_.getInt64(1), "", true, true);
    i_->addIncoming(i1, latch);
    for (size_t k = 0; k < next.size(); ++k)
      carried_[k]->addIncoming(next[k], latch);
    b_.CreateCondBr(b_.CreateICmpULT(i1, b_.getInt64(count_)), header_, exit_);
    b_.SetInsertPoint(exit_);
  }

private:
  llvm::IRBuilder<> &b_;
  uint32_t count_;
  llvm::BasicBlock *entry_, *header_, *exit_;
  llvm::PHINode *i_;
  std::vector<llvm::PHINode *> carried_;
  std::vector<llvm::Value *> columns_;
};

/// Emits the body of `lf` (a part signature, tmp unused): the loop's stores
/// for i in [0, count), the return code carried through the iterations.
void emitLoop(llvm::Module &m, const PlanLoop &loop, llvm::Function *lf) {
  llvm::IRBuilder<> b(m.getContext());
  CountedLoop cl(b, m, loop, lf, {b.getInt32(0)});
  ChunkEmitter::Args args{lf->getArg(0), lf->getArg(1), lf->getArg(2),
                          lf->getArg(3), lf->getArg(4), lf->getArg(5),
                          lf->getArg(6), nullptr};
  llvm::Value *rc = ChunkEmitter(b, m, loop.body, loop.body.chunks[0], args,
                                 &cl.columns(), cl.carried(0))
                        .emit();
  cl.close({rc});
  b.CreateRet(rc);
}

/// Emits `rf`: double (t, y, yp, p, cj, acc, int *err) folding the
/// reduction's terms into acc in order; *err (when not null) is set to
/// whether a term hit a domain error.
void emitReduction(llvm::Module &m, const PlanLoop &r, llvm::Function *rf) {
  llvm::IRBuilder<> b(m.getContext());
  CountedLoop cl(b, m, r, rf, {rf->getArg(5), b.getFalse()});
  ChunkEmitter::Args args{rf->getArg(0), rf->getArg(1), rf->getArg(2),
                          rf->getArg(3), rf->getArg(4), nullptr,
                          nullptr, nullptr};
  ChunkEmitter body(b, m, r.body, r.body.chunks[0], args, &cl.columns());
  body.emit();
  uint32_t root = r.body.nodes.size() - 1;
  llvm::Value *acc = r.subtract ? b.CreateFSub(cl.carried(0), body.result(root))
                                : b.CreateFAdd(cl.carried(0), body.result(root));
  llvm::Value *err = b.CreateOr(cl.carried(1), body.resultError(root));
  cl.close({acc, err});
  if (r.body.nodes[root].mayFail) {
    llvm::Value *out = rf->getArg(6);
    auto *store = llvm::BasicBlock::Create(m.getContext(), "store_error", rf);
    auto *done = llvm::BasicBlock::Create(m.getContext(), "done", rf);
    b.CreateCondBr(b.CreateIsNotNull(out), store, done);
    b.SetInsertPoint(store);
    b.CreateStore(b.CreateZExt(err, b.getInt32Ty()), out);
    b.CreateBr(done);
    b.SetInsertPoint(done);
  }
  b.CreateRet(acc);
}

/// Emits one plan function with its exported C ABI signature.
void emitFunction(llvm::Module &m, const CodePlan &plan,
                  const PlanFunction &fn) {
  llvm::LLVMContext &ctx = m.getContext();
  llvm::IRBuilder<> b(ctx);
  llvm::Type *dbl = b.getDoubleTy(), *ptr = b.getPtrTy(), *i32 = b.getInt32Ty();

  // Exported signature per FnSig.
  bool state = fn.sig == FnSig::State; // (t, y, p, out): no yp
  std::vector<llvm::Type *> params = {dbl, ptr, ptr};
  if (!state)
    params.push_back(ptr);
  if (fn.sig == FnSig::Jacobian)
    params.push_back(dbl);
  params.push_back(ptr);
  if (fn.sig == FnSig::InitJacobian)
    params.push_back(ptr);
  auto *f = llvm::Function::Create(llvm::FunctionType::get(i32, params, false),
                                   llvm::Function::ExternalLinkage,
                                   functionSymbol(plan, fn), m);
  f->addFnAttr(llvm::Attribute::NoUnwind);
  ChunkEmitter::Args args{};
  auto arg = [&](unsigned i) -> llvm::Value * { return f->getArg(i); };
  args.t = arg(0);
  args.y = arg(1);
  // A function over (t, y) hands its chunks y as the never-read yp (a
  // dereferenceable pointer, unlike null).
  args.yp = state ? args.y : arg(2);
  args.p = state ? arg(2) : arg(3);
  unsigned next = state ? 3 : 4;
  llvm::Value *nullPtr = llvm::ConstantPointerNull::get(b.getPtrTy());
  args.cj = fn.sig == FnSig::Jacobian ? arg(next++)
                                      : llvm::ConstantFP::get(dbl, 0.0);
  args.out0 = arg(next++);
  args.out1 = fn.sig == FnSig::InitJacobian ? arg(next++) : nullPtr;
  std::vector<unsigned> outs;
  for (unsigned i = state ? 3 : 4; i < f->arg_size(); ++i)
    if (f->getArg(i)->getType()->isPointerTy())
      outs.push_back(i);
  if (state)
    setPointerAttributes(plan, f, {1}, outs, 2);
  else
    setPointerAttributes(plan, f, {1, 2, 3}, outs);

  std::vector<llvm::Function *> reductions;
  auto *reduceTy = llvm::FunctionType::get(
      dbl, {dbl, ptr, ptr, ptr, dbl, dbl, ptr}, false);
  for (size_t r = 0; r < fn.reductions.size(); ++r) {
    auto *rf = llvm::Function::Create(
        reduceTy, llvm::Function::InternalLinkage,
        functionSymbol(plan, fn) + ".reduce" + std::to_string(r), m);
    rf->addFnAttr(llvm::Attribute::NoInline);
    rf->addFnAttr(llvm::Attribute::NoUnwind);
    setPointerAttributes(plan, rf, {1, 2, 3}, {6});
    emitReduction(m, fn.reductions[r], rf);
    reductions.push_back(rf);
  }

  auto *entry = llvm::BasicBlock::Create(ctx, "entry", f);
  b.SetInsertPoint(entry);
  for (unsigned i = 0; i < 2; ++i)
    if (fn.zeroFill[i])
      b.CreateMemSet(i ? args.out1 : args.out0, b.getInt8(0),
                     uint64_t(fn.zeroFill[i]) * 8, llvm::MaybeAlign(8));

  if (fn.chunks.size() == 1 && fn.loops.empty()) {
    args.tmp = nullPtr;
    ChunkEmitter ce(b, m, fn, fn.chunks[0], args);
    ce.setReductions(&reductions);
    b.CreateRet(ce.emit());
    return;
  }

  // Scratch array for values crossing chunks.
  uint64_t bytes = uint64_t(fn.numSpillSlots) * 8;
  bool heap = bytes > kMaxStackScratch;
  llvm::FunctionCallee mallocFn, freeFn;
  llvm::Value *tmp = nullPtr;
  if (heap) {
    mallocFn = m.getOrInsertFunction("malloc", ptr, b.getInt64Ty());
    freeFn = m.getOrInsertFunction("free", b.getVoidTy(), ptr);
    tmp = b.CreateCall(mallocFn, {b.getInt64(bytes)});
  } else if (fn.chunks.size() > 1) {
    tmp = b.CreateAlloca(dbl, b.getInt64(std::max<uint64_t>(1, fn.numSpillSlots)));
  }
  auto *partTy = llvm::FunctionType::get(
      i32, {dbl, ptr, ptr, ptr, dbl, ptr, ptr, ptr}, false);
  auto newPart = [&](const std::string &suffix) {
    auto *pf = llvm::Function::Create(partTy, llvm::Function::InternalLinkage,
                                      functionSymbol(plan, fn) + suffix, m);
    pf->addFnAttr(llvm::Attribute::NoInline);
    pf->addFnAttr(llvm::Attribute::NoUnwind);
    setPointerAttributes(plan, pf, {1, 2, 3}, {5, 6, 7});
    return pf;
  };
  // The straight-line chunks, then the loops: each a non-inlined function,
  // called in order while no error has been returned.
  std::vector<llvm::Function *> parts;
  bool straight = !fn.stores.empty();
  for (size_t c = 0; straight && c < fn.chunks.size(); ++c) {
    llvm::Function *cf = newPart(".chunk" + std::to_string(c));
    llvm::IRBuilder<> cb(llvm::BasicBlock::Create(ctx, "entry", cf));
    ChunkEmitter::Args ca{cf->getArg(0), cf->getArg(1), cf->getArg(2),
                          cf->getArg(3), cf->getArg(4), cf->getArg(5),
                          cf->getArg(6), cf->getArg(7)};
    ChunkEmitter ce(cb, m, fn, fn.chunks[c], ca);
    ce.setReductions(&reductions);
    cb.CreateRet(ce.emit());
    parts.push_back(cf);
  }
  for (size_t l = 0; l < fn.loops.size(); ++l) {
    llvm::Function *lf = newPart(".loop" + std::to_string(l));
    emitLoop(m, fn.loops[l], lf);
    parts.push_back(lf);
  }

  auto *done = llvm::BasicBlock::Create(ctx, "done", f);
  llvm::IRBuilder<> db(done);
  auto *rcPhi = db.CreatePHI(i32, std::max<size_t>(1, parts.size()));
  if (heap)
    db.CreateCall(freeFn, {tmp});
  db.CreateRet(rcPhi);
  if (parts.empty()) {
    rcPhi->addIncoming(b.getInt32(0), b.GetInsertBlock());
    b.CreateBr(done);
  }
  for (size_t c = 0; c < parts.size(); ++c) {
    llvm::Value *rc = b.CreateCall(
        parts[c], {args.t, args.y, args.yp, args.p, args.cj, args.out0,
                   args.out1, tmp});
    rcPhi->addIncoming(rc, b.GetInsertBlock());
    if (c + 1 == parts.size()) {
      b.CreateBr(done);
    } else {
      auto *cont = llvm::BasicBlock::Create(ctx, "cont", f, done);
      b.CreateCondBr(b.CreateICmpEQ(rc, b.getInt32(0)), cont, done);
      b.SetInsertPoint(cont);
    }
  }
}

void initializeLlvm() {
  static std::once_flag once;
  std::call_once(once, [] {
    // LLVM is built without exceptions: where its own allocation fails it
    // would abort with a trace. Say what happened in our words and exit 1,
    // as the driver does for std::bad_alloc (docs/exit-codes.md).
    llvm::install_bad_alloc_error_handler(
        [](void *, const char *, bool) {
          static const char msg[] =
              "ldaec: error: out of memory (in LLVM code generation)\n";
          (void)!::write(2, msg, sizeof msg - 1);
          ::_exit(1);
        });
    llvm::InitializeNativeTarget();
    llvm::InitializeNativeTargetAsmPrinter();
    // The post-RA list scheduler is quadratic in the memory operations of
    // a block and buys little on out-of-order x86 cores; it was a third of
    // the backend's time on large models.
    const char *args[] = {"ldaec", "-post-RA-scheduler=false"};
    llvm::cl::ParseCommandLineOptions(2, args, "", &llvm::nulls());
  });
}

Error toError(llvm::Error e) { return Error{llvm::toString(std::move(e))}; }

/// Plans up to this many nodes get the full O2 pipeline and the optimizing
/// instruction selector. Above it, compile time would dominate (LLVM's
/// machine scheduler and SelectionDAG cost ~5 ms per RC-ladder element), so
/// large models get the O1 IR pipeline and FastISel: about 10x faster to
/// compile, still each shared node computed once (docs/codegen.md).
constexpr size_t kFullOptimizationNodes = 5000;
/// Above this many, no IR pipeline at all: O1's instruction combining
/// grows faster than the code (a 150k-node symbolic Jacobian of an SGA
/// vector field took 24 s of CPU, 88% in LLVM's passes); the plan already
/// computes each shared node once.
constexpr size_t kLightOptimizationNodes = 60000;

OptTier optTier(const CodePlan &plan) {
  size_t nodes = planNodes(plan);
  return nodes <= kFullOptimizationNodes    ? OptTier::O2
         : nodes <= kLightOptimizationNodes ? OptTier::O1
                                            : OptTier::O0;
}

/// Host target machine and its builder.
Expected<std::unique_ptr<llvm::TargetMachine>>
hostMachine(llvm::orc::JITTargetMachineBuilder &jtmb, OptTier tier) {
  jtmb.setCodeGenOptLevel(tier == OptTier::O2 ? llvm::CodeGenOptLevel::Default
                                              : llvm::CodeGenOptLevel::None);
  auto tm = jtmb.createTargetMachine();
  if (!tm)
    return toError(tm.takeError());
  return std::move(*tm);
}

class LljitCode : public JitCode {
public:
  // Declared first, destroyed last: the JIT's compiler points at it.
  std::unique_ptr<ObjectFileCache> cacheOwner;
  std::unique_ptr<llvm::orc::LLJIT> jit;
  std::vector<uintptr_t> addresses;
  uintptr_t address(int i) const override { return addresses[i]; }
};

} // namespace

std::unique_ptr<llvm::Module> emitModule(const CodePlan &plan,
                                         llvm::LLVMContext &ctx) {
  auto m = std::make_unique<llvm::Module>(plan.symbolName, ctx);
  for (const PlanFunction &fn : plan.functions)
    emitFunction(*m, plan, fn);
  assert(!llvm::verifyModule(*m, &llvm::errs()));
  return m;
}

const char *optTierName(OptTier tier) {
  switch (tier) {
  case OptTier::O2:
    return "O2";
  case OptTier::O1:
    return "O1";
  case OptTier::O0:
    return "O0";
  }
  return "?";
}

void optimizeModule(llvm::Module &m, llvm::TargetMachine &tm, OptTier tier) {
  if (tier == OptTier::O0)
    return;
  llvm::LoopAnalysisManager lam;
  llvm::FunctionAnalysisManager fam;
  llvm::CGSCCAnalysisManager cgam;
  llvm::ModuleAnalysisManager mam;
  llvm::PassBuilder pb(&tm);
  pb.registerModuleAnalyses(mam);
  pb.registerCGSCCAnalyses(cgam);
  pb.registerFunctionAnalyses(fam);
  pb.registerLoopAnalyses(lam);
  pb.crossRegisterProxies(lam, fam, cgam, mam);
  llvm::ModulePassManager mpm =
      pb.buildPerModuleDefaultPipeline(tier == OptTier::O2
                                           ? llvm::OptimizationLevel::O2
                                           : llvm::OptimizationLevel::O1);
  mpm.run(m, mam);
}

namespace {

Expected<std::unique_ptr<JitCode>>
compileWithLljit(const CodePlan &plan, const std::string &cacheDir) {
  initializeLlvm();
  auto jtmb = llvm::orc::JITTargetMachineBuilder::detectHost();
  if (!jtmb)
    return toError(jtmb.takeError());
  OptTier tier = optTier(plan);
  auto tm = hostMachine(*jtmb, tier);
  if (!tm)
    return Error{tm.error()};

  auto ctx = std::make_unique<llvm::LLVMContext>();
  std::unique_ptr<llvm::Module> m = emitModule(plan, *ctx);
  m->setDataLayout((*tm)->createDataLayout());
  m->setTargetTriple((*tm)->getTargetTriple().str());
  // The cache is keyed by the module before optimization, so a hit skips
  // both the O2 pipeline and code generation.
  std::unique_ptr<ObjectFileCache> cache;
  std::unique_ptr<llvm::MemoryBuffer> cached;
  if (!cacheDir.empty()) {
    cache = std::make_unique<ObjectFileCache>(cacheDir, *m, **tm,
                                              optTierName(tier));
    cached = cache->load();
  }
  if (!cached)
    optimizeModule(*m, **tm, tier);

  llvm::orc::LLJITBuilder builder;
  builder.setJITTargetMachineBuilder(*jtmb);
  if (cache && !cached)
    builder.setCompileFunctionCreator(
        [c = cache.get()](llvm::orc::JITTargetMachineBuilder b)
            -> llvm::Expected<
                std::unique_ptr<llvm::orc::IRCompileLayer::IRCompiler>> {
          auto machine = b.createTargetMachine();
          if (!machine)
            return machine.takeError();
          return std::make_unique<llvm::orc::TMOwningSimpleCompiler>(
              std::move(*machine), c);
        });
  auto jit = builder.create();
  if (!jit)
    return toError(jit.takeError());
  llvm::orc::JITDylib &lib = (*jit)->getMainJITDylib();
  // libm and libc (malloc/free) come from the running process.
  auto gen = llvm::orc::DynamicLibrarySearchGenerator::GetForCurrentProcess(
      (*jit)->getDataLayout().getGlobalPrefix());
  if (!gen)
    return toError(gen.takeError());
  lib.addGenerator(std::move(*gen));
  // External function wrappers are already loaded in this process; the
  // cached object names them by symbol, so a hit resolves them the same way.
  if (!plan.externals.empty()) {
    llvm::orc::SymbolMap wrappers;
    for (const PlanExternal &x : plan.externals) {
      if (!x.address)
        return Error{"external function '" + x.name + "' is not loaded"};
      wrappers[(*jit)->mangleAndIntern(x.symbol)] = {
          llvm::orc::ExecutorAddr(x.address),
          llvm::JITSymbolFlags::Exported | llvm::JITSymbolFlags::Callable};
    }
    if (auto e = lib.define(llvm::orc::absoluteSymbols(std::move(wrappers))))
      return toError(std::move(e));
  }
  const bool hit = cached != nullptr;
  if (hit) {
    if (auto e = (*jit)->addObjectFile(std::move(cached)))
      return toError(std::move(e));
  } else if (auto e = (*jit)->addIRModule(llvm::orc::ThreadSafeModule(
                 std::move(m), std::move(ctx)))) {
    return toError(std::move(e));
  }

  auto code = std::make_unique<LljitCode>();
  code->cache = !cache ? CacheUse::None : hit ? CacheUse::Hit : CacheUse::Miss;
  // The lookups compile the module (on a miss, which stores it).
  for (const PlanFunction &fn : plan.functions) {
    auto addr = (*jit)->lookup(functionSymbol(plan, fn));
    if (!addr)
      return toError(addr.takeError());
    code->addresses.push_back(addr->getValue());
  }
  code->jit = std::move(*jit);
  code->cacheOwner = std::move(cache);
  return std::unique_ptr<JitCode>(std::move(code));
}

std::string printOptimizedModule(const CodePlan &plan) {
  initializeLlvm();
  llvm::LLVMContext ctx;
  std::unique_ptr<llvm::Module> m = emitModule(plan, ctx);
  if (auto jtmb = llvm::orc::JITTargetMachineBuilder::detectHost()) {
    OptTier tier = optTier(plan);
    if (auto tm = hostMachine(*jtmb, tier)) {
      m->setDataLayout((*tm)->createDataLayout());
      m->setTargetTriple((*tm)->getTargetTriple().str());
      optimizeModule(*m, **tm, tier);
    }
  } else {
    llvm::consumeError(jtmb.takeError());
  }
  std::string text;
  llvm::raw_string_ostream os(text);
  m->print(os, nullptr);
  return text;
}

} // namespace

const JitBackend &llvmBackend() {
  static const JitBackend backend = [] {
    JitBackend b;
    b.compile = compileWithLljit;
    b.print = printOptimizedModule;
    return b;
  }();
  return backend;
}

} // namespace ldae::codegen

/// The module's one exported symbol (kJitEntrySymbol); everything else in
/// it is hidden, so its copies of the shared plan rules never interpose.
extern "C" __attribute__((visibility("default"))) const ldae::codegen::JitBackend *
ldae_jit_backend() {
  return &ldae::codegen::llvmBackend();
}
