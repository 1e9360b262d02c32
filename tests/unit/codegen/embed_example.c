/* Calling a model emitted by `ldaec model.lsd --emit c -o model.c` through
   the C ABI (docs/embedding-c.md): evaluates the residual of the first state
   set and its Jacobian at the model's start values.
   Build: cc -O2 -I<ldaec>/runtime/include embed_example.c model.c -lm */
#include <stdio.h>
#include <stdlib.h>

#include "ldae/model.h"

const ldae_model *ldae_get_model(void); /* defined in model.c */

int main(void) {
  const ldae_model *m = ldae_get_model();
  const ldae_state_set *set = &m->state_sets[0];
  double *r = malloc(m->n * sizeof(double));
  double *jac = malloc((set->jac_nnz + 1) * sizeof(double));
  int i, j, k, rc;

  printf("model %s: %d unknowns, %d state sets, %d nonzeros\n", m->name, m->n,
         m->n_state_sets, set->jac_nnz);
  rc = set->residual(0.0, m->start_y, m->start_yp, m->param_values, r);
  if (rc > 0) /* a domain error in residual row rc - 1 */
    printf("domain error in row %d\n", rc - 1);
  for (i = 0; i < m->n; ++i)
    printf("r[%d] = %.17g\n", i, r[i]);
  /* dF/dy + cj dF/dy' with cj = 10, in the CSC pattern of the state set. */
  rc = set->jacobian_csc(0.0, m->start_y, m->start_yp, m->param_values, 10.0,
                         jac);
  for (j = 0; rc == 0 && j < m->n; ++j)
    for (k = set->jac_colptr[j]; k < set->jac_colptr[j + 1]; ++k)
      printf("J[%d,%d] = %.17g\n", set->jac_rowind[k], j, jac[k]);
  free(r);
  free(jac);
  return rc == 0 ? 0 : 1;
}
