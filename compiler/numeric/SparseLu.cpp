// KLU behind a small RAII class (see SparseLu.h).
#include "numeric/SparseLu.h"

#include <klu.h>

#include <algorithm>
#include <cmath>

namespace ldae::numeric {

double CscMatrix::maxAbs() const {
  double m = 0;
  for (double v : values)
    m = std::max(m, std::fabs(v));
  return m;
}

void CscMatrix::multiply(const double *x, double *y) const {
  std::fill(y, y + n, 0.0);
  for (int c = 0; c < n; ++c)
    for (int q = colptr[c]; q < colptr[c + 1]; ++q)
      y[rowind[q]] += values[q] * x[c];
}

CscMatrix CscMatrix::transposed() const {
  CscMatrix t;
  t.n = n;
  t.colptr.assign(n + 1, 0);
  t.rowind.resize(nnz());
  t.values.resize(nnz());
  for (int q = 0; q < nnz(); ++q)
    ++t.colptr[rowind[q] + 1];
  for (int r = 0; r < n; ++r)
    t.colptr[r + 1] += t.colptr[r];
  std::vector<int> next(t.colptr.begin(), t.colptr.end() - 1);
  for (int c = 0; c < n; ++c)
    for (int q = colptr[c]; q < colptr[c + 1]; ++q) {
      int dst = next[rowind[q]]++;
      t.rowind[dst] = c;
      t.values[dst] = values[q];
    }
  return t;
}

struct SparseLu::Impl {
  klu_common common;
  klu_symbolic *symbolic = nullptr;
  klu_numeric *numeric = nullptr;
  const CscMatrix *a = nullptr;
  int singularCol = -1;

  void release() {
    // klu_free_* only fail on a null Common, which is never the case here.
    if (numeric)
      klu_free_numeric(&numeric, &common);
    if (symbolic)
      klu_free_symbolic(&symbolic, &common);
    numeric = nullptr;
    symbolic = nullptr;
    a = nullptr;
  }
};

SparseLu::SparseLu() : impl_(std::make_unique<Impl>()) {
  klu_defaults(&impl_->common);
}

SparseLu::~SparseLu() { impl_->release(); }

bool SparseLu::factor(const CscMatrix &a) {
  Impl &I = *impl_;
  I.release();
  I.singularCol = -1;
  if (a.n == 0) {
    I.a = &a;
    return true;
  }
  // KLU takes non-const pointers but does not modify its inputs.
  int *ap = const_cast<int *>(a.colptr.data());
  int *ai = const_cast<int *>(a.rowind.data());
  double *ax = const_cast<double *>(a.values.data());
  I.symbolic = klu_analyze(a.n, ap, ai, &I.common);
  if (!I.symbolic)
    return false;
  I.numeric = klu_factor(ap, ai, ax, I.symbolic, &I.common);
  if (!I.numeric || I.common.status != KLU_OK) {
    if (I.common.status == KLU_SINGULAR)
      I.singularCol = I.common.singular_col;
    I.release();
    return false;
  }
  I.a = &a;
  return true;
}

double SparseLu::rcondEstimate() {
  Impl &I = *impl_;
  if (!I.a)
    return 0;
  if (I.a->n == 0)
    return 1;
  if (!klu_condest(const_cast<int *>(I.a->colptr.data()),
                   const_cast<double *>(I.a->values.data()), I.symbolic,
                   I.numeric, &I.common) ||
      !(I.common.condest > 0))
    return 0;
  return 1 / I.common.condest;
}

bool SparseLu::solve(double *b, bool transposed) {
  Impl &I = *impl_;
  if (!I.a)
    return false;
  if (I.a->n == 0)
    return true;
  int n = I.a->n;
  return transposed ? klu_tsolve(I.symbolic, I.numeric, n, 1, b, &I.common)
                    : klu_solve(I.symbolic, I.numeric, n, 1, b, &I.common);
}

int SparseLu::singularColumn() const { return impl_->singularCol; }

} // namespace ldae::numeric
