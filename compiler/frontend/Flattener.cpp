// The flattening of one model, start to end: command-line parameter
// overrides, the instance tree, equations, connection sets, and the checks
// that need everything (unused overrides).
#include "frontend/Flattener.h"

#include <set>

namespace ldae::frontend {

Flattener::Flattener(ClassTable &classes, DiagnosticEngine &diags,
                     const FrontendOptions &opts)
    : classes_(classes), diags_(diags), opts_(opts) {}

Flattener::~Flattener() = default;

bool Flattener::overBudget() {
  if (!model_)
    return false;
  if (instances_ > kMaxInstances)
    return true; // reported by countInstances
  size_t scalars = model_->variables.size() + model_->parameters.size() +
                   model_->equations.size() + model_->initialEquations.size();
  if (scalars <= kMaxScalars)
    return false;
  if (!budgetReported_) {
    budgetReported_ = true;
    report(DiagId::ErrModelTooLarge, model_->loc,
           {std::to_string(kMaxScalars)});
  }
  return true;
}

void Flattener::reportUnusedOverrides() {
  std::vector<std::string> paramNames, startNames;
  std::set<std::string> varNames;
  for (const ir::Parameter &p : model_->parameters)
    paramNames.push_back(p.name);
  for (const ir::Variable &v : model_->variables) {
    startNames.push_back(v.name + kStartSuffix);
    varNames.insert(v.name);
  }
  for (const auto &[name, entry] : overrides_) {
    if (entry.second)
      continue;
    // `x.start=...` sets a variable's start value, `p=...` a parameter;
    // `x=...` for a variable is most likely the former.
    bool isStart = name.ends_with(kStartSuffix);
    std::string best = isStart              ? closestName(name, startNames)
                       : varNames.count(name) ? name + kStartSuffix
                                              : closestName(name, paramNames);
    const char *kind = isStart ? "variable" : "parameter";
    if (best.empty())
      report(DiagId::ErrUnknownOverride, SourceLoc{}, {name, kind});
    else
      report(DiagId::ErrUnknownOverrideSuggest, SourceLoc{}, {name, kind, best});
  }
}

std::unique_ptr<ir::Model> Flattener::flatten(const ast::ClassDef &cls) {
  model_ = std::make_unique<ir::Model>();
  model_->name = cls.name;
  model_->loc = cls.loc;
  diff_ = std::make_unique<ir::Differentiator>(model_->ctx());

  for (const std::string &o : opts_.paramOverrides) {
    ParamOverride p = parseParamOverride(o);
    if (p.name.empty() || !p.value) {
      report(DiagId::ErrBadOverride, SourceLoc{}, {o});
      continue;
    }
    overrides_[p.name] = {*p.value, false};
  }

  root_ = std::make_unique<InstNode>();
  root_->name = cls.name;
  root_->cls = &cls;
  root_->typeName = cls.name;
  root_->isConnector = cls.kind == ast::ClassKind::Connector;
  root_->state = InstNode::State::Elaborating;
  elaborateInstance(*root_);
  root_->state = InstNode::State::Done;
  readExperiment(cls, *root_);
  checkUsedVersions(cls);
  if (!expandables_.empty()) {
    connectSweep_ = expandSweep_ = true;
    collectConnects(*root_);
    for (auto &[name, added] : addedInners_)
      collectConnects(*added.node);
    connectSweep_ = expandSweep_ = false;
    completeExpandableConnectors();
  }
  connectSweep_ = true;
  collectConnects(*root_);
  for (auto &[name, added] : addedInners_)
    collectConnects(*added.node);
  connectSweep_ = false;
  connectsCollected_ = true;
  flattenInstance(*root_);
  for (auto &[name, added] : addedInners_)
    flattenInstance(*added.node);
  buildConnectionEquations();

  reportUnusedOverrides();
  if (diags_.hasErrors())
    return nullptr;
  return std::move(model_);
}

} // namespace ldae::frontend
