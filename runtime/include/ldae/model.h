/* The C ABI of a compiled ldaec model.
 *
 * One struct describes a model: sizes, names, start and nominal values,
 * which unknowns are differential, and function pointers for the residual,
 * IDA's iteration matrix, roots, and the geometric method's slots. The LLVM
 * JIT, the interpreter and the emitted C file all fill this same struct; the
 * runtime (IDA/CVODE drivers) only ever sees this struct.
 *
 * Conventions:
 *  - y, yp, r have length n; p has length n_params.
 *  - Every function returns 0 on success, a positive value on a recoverable
 *    failure (a domain error: 1 + the index of the residual row where it
 *    happened, so messages can name the equation), negative if fatal.
 *  - Matrices are column-major (dense) or CSC with the fixed pattern given
 *    in the struct (sparse).
 *  - Plain C99; no dependency beyond the C standard library.
 */
#ifndef LDAE_MODEL_H
#define LDAE_MODEL_H

/* The name of homotopy()'s continuation parameter (see param_names). */
#define LDAE_HOMOTOPY_LAMBDA "homotopy.lambda"

#ifdef __cplusplus
extern "C" {
#endif

#define LDAE_ABI_VERSION 12

/* r = F(t, y, y', p) */
typedef int (*ldae_residual_fn)(double t, const double *y, const double *yp,
                                const double *p, double *r);
/* J = dF/dy + cj * dF/dy'; dense n*n column-major. */
typedef int (*ldae_jacobian_dense_fn)(double t, const double *y,
                                      const double *yp, const double *p,
                                      double cj, double *J);
/* The nonzeros of dF/dy + cj * dF/dy' in the struct's CSC pattern order. */
typedef int (*ldae_jacobian_csc_fn)(double t, const double *y,
                                    const double *yp, const double *p,
                                    double cj, double *values);
/* g = root functions at (t, y, y'); events happen where a component
   changes sign. */
typedef int (*ldae_roots_fn)(double t, const double *y, const double *yp,
                             const double *p, double *g);
/* out = reported variables (see output_names) from (t, y, y'). */
typedef int (*ldae_outputs_fn)(double t, const double *y, const double *yp,
                               const double *p, double *out);
/* Initialization: r = extra conditions at the start (initial equations),
   and their Jacobians w.r.t. y and y': dense (n_init x n, column-major,
   into Jy and Jyp), or CSC (the nonzeros of the struct's init pattern, in
   pattern order, into Jy and Jyp). */
typedef int (*ldae_init_residual_fn)(double t, const double *y,
                                     const double *yp, const double *p,
                                     double *r);
typedef int (*ldae_init_jacobian_fn)(double t, const double *y,
                                     const double *yp, const double *p,
                                     double *Jy, double *Jyp);
/* Pivot matrix of a state set (m x m, column-major) at (t, y). */
typedef int (*ldae_pivot_fn)(double t, const double *y, const double *yp,
                             const double *p, double *M);
/* Geometric-method slots (--method sga|ode): x' = f(t, x, p) on the final
   constraint manifold; c(t, x, p) = 0 its constraints; Jc = dc/dx
   (n_constraints x n_ode, column-major). The code generators leave ode_rhs
   NULL: the runtime solves the linearly implicit rows for f (see
   n_ode). */
typedef int (*ldae_ode_rhs_fn)(double t, const double *x, const double *p,
                               double *xdot);
typedef int (*ldae_constraints_fn)(double t, const double *x, const double *p,
                                   double *c);
typedef int (*ldae_constraint_jacobian_fn)(double t, const double *x,
                                           const double *p, double *Jc);

/* What a discrete value is (ldae_model::discrete_kind). */
enum {
  LDAE_DISCRETE_VARIABLE = 0, /* a Boolean, Integer or discrete Real variable,
                                 or one assigned in a when-clause */
  LDAE_DISCRETE_RELATION = 1, /* the value (1/0) of a relation on continuous
                                 unknowns or time, frozen between events */
  LDAE_DISCRETE_WHEN = 2,     /* the value of a when-clause's condition */
  LDAE_DISCRETE_SAMPLE = 3,   /* sample(start, interval): 1 at its instants,
                                 set by the runtime */
  LDAE_DISCRETE_INITIAL = 4,  /* initial(): 1 during the initial event */
  LDAE_DISCRETE_TERMINAL = 5, /* terminal(): 1 during the terminal event */
  LDAE_DISCRETE_DELAY = 6     /* delay(e, d) of an e that changes at events
                                 only (ABI 10): e's value d earlier, set by
                                 the runtime at time events; the update
                                 copies it, but gives e itself during the
                                 initial event and when d <= 0 */
};

/* One choice of states for dynamic state selection. All sets share the
   unknown layout; they differ in residuals and differential flags. */
typedef struct ldae_state_set {
  const int *is_differential;          /* n: 1 differential, 0 algebraic */
  ldae_residual_fn residual;
  ldae_jacobian_dense_fn jacobian_dense;
  ldae_jacobian_csc_fn jacobian_csc;   /* pattern: jac_colptr/jac_rowind */
  int jac_nnz;
  const int *jac_colptr;               /* n + 1 */
  const int *jac_rowind;               /* jac_nnz */
  int pivot_size;                      /* m; 0 for a static set */
  ldae_pivot_fn pivot;
  const char *description;             /* e.g. "states: y, der(y)" */
} ldae_state_set;

/* A block whose states the runtime chooses (ABI 8; docs/runtime.md,
   "Dynamic state selection"): `rows` equations over `forced` columns that
   are dummy derivatives always and `candidates` columns of which
   rows - forced are dummies at any time; the others are the states
   x_k = sum_j A[k][j] c_j, unknowns state_slots[k] of y with their own
   residuals x - A c and der(x) - A der(c). A, 0/1 and column-major
   (n_states x candidates, n_states = forced + candidates - rows), is
   p[param ...]: changing it (and setting x, der(x) to A c, A der(c))
   switches the states without leaving the state set. */
typedef struct ldae_dynamic_set {
  int rows, forced, candidates;
  ldae_pivot_fn jacobian;   /* rows x (forced + candidates), column-
                               major, the forced columns first */
  ldae_pivot_fn values;     /* 2 * candidates: c, then der(c) */
  int param;                /* p index of A */
  const double *start;      /* A at the start (n_states x candidates) */
  const int *state_slots;   /* n_states */
  const char *const *names; /* candidates */
} ldae_dynamic_set;

typedef struct ldae_model {
  int abi_version;                     /* LDAE_ABI_VERSION */
  const char *name;

  int n;                               /* unknowns */
  const char *const *var_names;        /* n */
  const double *start_y;               /* n */
  const double *start_yp;              /* n */
  const double *nominal;               /* n, > 0 */
  const int *fixed;                    /* n: start value is a condition */

  int n_params;
  /* n_params; a parameter named LDAE_HOMOTOPY_LAMBDA is the compiler's
     continuation parameter of homotopy() (1 = the actual model), set by the
     runtime's initialization and not among the default outputs. */
  const char *const *param_names;
  const double *param_values;          /* n_params: defaults */

  int n_state_sets;                    /* >= 1; state_sets[0] is the start */
  const ldae_state_set *state_sets;

  int n_init;                          /* extra initial conditions */
  ldae_init_residual_fn init_residual;
  ldae_init_jacobian_fn init_jacobian;

  int n_roots;
  ldae_roots_fn roots;

  int n_outputs;                       /* reported columns after `time` */
  const char *const *output_names;
  ldae_outputs_fn outputs;

  /* Constraints of the original model kept by the reduced one; their
     largest residual is reported as drift (n_drift may be 0). */
  int n_drift;
  ldae_residual_fn drift;              /* writes n_drift values */

  /* Geometric method (SGA) slots. n_ode = n when the only state set's
     rows are linear in y' with every unknown differential and dF/dy'
     nonsingular on the constraint manifold (--method sga|ode): CVODE then
     integrates y' = f(t, y) solving dF/dy' f = -F(t, y, 0); 0 otherwise.
     n_constraints, constraints, constraint_jacobian: every constraint
     generation c(t, y) = 0 of that system (the start is projected onto
     them; see project_constraints). */
  int n_ode;
  int n_constraints;
  ldae_ode_rhs_fn ode_rhs;
  ldae_constraints_fn constraints;
  ldae_constraint_jacobian_fn constraint_jacobian;

  /* Source location of the equation behind each residual row (n), for
     failure messages: "file:line". May be NULL. */
  const char *const *residual_origin;

  /* Simulation defaults from the experiment annotation (NaN when unset). */
  double start_time, stop_time, tolerance, interval;

  /* The initial equations' Jacobians dG/dy and dG/dy' in one CSC pattern
     (n_init rows, n columns; the union of both patterns), for the sparse
     initialization of large models. Always present; init_jacobian (dense)
     is NULL above LDAE_DENSE_THRESHOLD unknowns, like jacobian_dense. */
  int init_jac_nnz;
  const int *init_jac_colptr;          /* n + 1 */
  const int *init_jac_rowind;          /* init_jac_nnz, rows < n_init */
  ldae_init_jacobian_fn init_jacobian_csc;

  /* Source location of the equation that computes each output (n_outputs,
     "file:line:col", "" where none: a state, an alias), for the failure
     message of an output that leaves its domain. May be NULL. */
  const char *const *output_origin;

  /* 1 when the model is an explicit ODE: one state set, every unknown
     differential, and row i of its residual is y'[i] - f_i(t, y) (the
     causal form "ODE"), so f(t, y) = -F(t, y, 0) and df/dy = -J(cj = 0).
     CVODE runs such a model; 0 otherwise. */
  int explicit_ode;

  /* 1 when every unknown belongs in the integrator's local error test: the
     system is of index 1 (every reduced one is). 0 when the algebraic
     unknowns are left out of it: a system handed over as written
     (`--method raw`) whose index exceeds one, where their errors do not
     follow the differential ones' (docs/runtime.md, "The error test"). */
  int algebraic_error_test;

  /* With n_ode = n: 1 when the solution is projected onto the constraints
     after each step (--method sga), 0 when only the start is (--method
     ode: the drift shows). */
  int project_constraints;

  /* The unknowns of the index-1 system that the causal form computes
     outside the integrator (y3 = 1 - y1 - y2 of Robertson): the error test
     still controls them through the states they are computed from
     (docs/runtime.md, "The error test"). z = tested(t, y, y', p)
     (n_tested values, nominal values tested_nominal) and dz/dy in the CSC
     pattern tested_jac_* (n_tested rows, n columns), written by
     tested_jacobian_csc called with cj = 0. n_tested may be 0. */
  int n_tested;
  const double *tested_nominal;        /* n_tested */
  ldae_outputs_fn tested;
  int tested_jac_nnz;
  const int *tested_jac_colptr;        /* n + 1 */
  const int *tested_jac_rowind;        /* tested_jac_nnz */
  ldae_jacobian_csc_fn tested_jacobian_csc;

  /* ---- Events (ABI 6; docs/events.md) ----
     The discrete state: n_discrete values kept by the run beside y. Every
     function of this struct receives them after the parameters:
       p[n_params + k]              discrete value k (frozen between events)
       p[n_params + n_discrete + k] its pre() value
     so p has n_params + 2 * n_discrete entries. Between events nothing
     changes them: a relation on continuous unknowns is read from its
     frozen value, so residuals and Jacobians stay smooth while the
     integrator steps, and `roots` tells when it would change. */
  int n_discrete;
  const char *const *discrete_names;   /* n_discrete: "heat", "h <= 0" */
  const double *discrete_start;        /* n_discrete: before the initial event */
  const int *discrete_kind;            /* n_discrete: LDAE_DISCRETE_* */
  /* Root j (of n_roots) is lhs - rhs of relation discrete value
     root_relation[j]: an event happens where it changes sign. */
  const int *root_relation;            /* n_roots */

  /* The event update, called at an event with the continuous point (t, y,
     y') and p's pre() values held: out = [the new value of each discrete
     value (n_discrete) | each reinit's value (n_reinit) | whether each
     reinit fired, 1/0 (n_reinit) | whether each terminate fired, 1/0
     (n_terminate)]. Relations are evaluated from y (not their frozen
     values), time relations as their right limit (`time > t0` is 1 at
     t0), discrete equations in dependency order, and a when-clause fires
     where its condition is 1 and its pre() is 0 (during the initial
     event only a condition with initial() fires); a variable assigned in a
     when-clause that does not fire keeps its pre() value. Sample, initial
     and terminal values are inputs: the update copies their current
     values. The runtime iterates: pre := current; update; apply reinits;
     re-initialize; until no discrete value changes (docs/events.md). */
  int n_reinit;
  const int *reinit_target;            /* n_reinit: unknown index in y */
  int n_terminate;
  const char *const *terminate_message; /* n_terminate */
  ldae_outputs_fn event_update;        /* NULL when n_discrete == 0 */

  /* Time events, hit exactly (a stop time of the integrator, no root
     search): out = [the threshold of each time relation (n_time_thresholds:
     `time >= t0` gives t0) | start and interval of each sample
     (2 * n_samples) | for each discrete value of kind LDAE_DISCRETE_DELAY,
     in discrete order: the delayed expression's current value, the delay
     time and the maximum delay (the delay time when none is given)]. They
     read only t, parameters and discrete values; the runtime evaluates
     them again after each event. */
  int n_time_thresholds;
  const int *threshold_relation;       /* n_time_thresholds: discrete index */
  int n_samples;
  const int *sample_discrete;          /* n_samples: discrete index */
  ldae_outputs_fn time_events;         /* NULL when there are none */

  /* assert(condition, message, level): out = 1/0 per assert, checked at
     every output row and event. Level 0 error (the run stops, status 3),
     1 warning (reported once). */
  int n_asserts;
  const char *const *assert_message;   /* n_asserts */
  const int *assert_level;             /* n_asserts */
  const char *const *assert_origin;    /* n_asserts: "file:line:col" */
  ldae_outputs_fn asserts;             /* NULL when n_asserts == 0 */
  /* ABI 11: values known only at run time in the messages (String(y) of
     an unknown). The asserts function writes after the n_asserts
     conditions the message values, assert i's at out[n_asserts +
     assert_value_begin[i] ... n_asserts + assert_value_begin[i + 1]).
     Value k shows in assert_message[i] as "\x1f<k>:<format>\x1f", format
     "g<significantDigits>,<minimumLength>,<leftJustified>" (an integral
     value printed as an integer, else %.<digits>g, padded to the length)
     or "%<printf conversion>" (String(x, format = ...)). NULL: none. */
  const int *assert_value_begin;       /* n_asserts + 1 */

  /* Variable structure: the discrete values whose values choose the
     branches of if-equations whose branches differ in incidence (an ideal
     switch). This model was compiled for mode_values of them; when an
     event changes one, the run asks for the model of the new mode
     (runtime SimOptions::modeProvider) and carries the point over by
     variable name. n_mode = 0: one structure. */
  int n_mode;
  const int *mode_discrete;            /* n_mode: discrete index */
  const double *mode_values;           /* n_mode */

  /* The jump rule (LANGUAGE.md "Initial values", seed 002) needs the
     pencil of the model as written, not of the reduced one:
     dummy_of[set][i] = j when unknown i is, in state set `set`, a dummy
     derivative standing for der(y[j]) (-1 otherwise); original_row[set][r]
     = 1 when residual row
     r of state set `set` is an equation of the model as written (0: made
     by index reduction, or a link row). May be NULL (every row original,
     no dummies). */
  const int *const *dummy_of;          /* n_state_sets x n */
  const int *const *original_row;      /* n_state_sets x n */

  /* ---- Results (ABI 7; docs/results.md) ----
     What a result file says of each reported column and parameter. Units
     and descriptions are "" where the model gives none. output_alias[k] is
     0 when output k is a value of its own, +(j + 1) when it equals output
     j, -(j + 1) when it equals minus output j (the `a = b` and `a = -b`
     that alias elimination removed): a .mat file stores the column once
     and refers to it with sign, as OpenModelica's and Dymola's do. May be
     NULL (no units, no descriptions, no aliases). */
  const char *const *output_unit;        /* n_outputs */
  const char *const *output_description; /* n_outputs */
  const int *output_alias;               /* n_outputs */
  const char *const *param_unit;         /* n_params */
  const char *const *param_description;  /* n_params */

  /* ---- Run-time parameters (ABI 7; docs/results.md) ----
     A parameter changed for a run (without recompiling) changes what
     reads it: bind(t0, y, y', p, out) writes the binding of each
     bound_params[j] at out[j], then the start value of each
     bound_starts[j] at out[n_bound_params + j], all evaluated over p.
     Applying the parameter part bind_passes times settles chains of
     bindings; a parameter given a value by the user keeps it.
     param_structural[k] = 1 when parameter k fixed the model's structure
     (an array size, a branch chosen, a subscript): a new value needs a
     recompile; 2 when it is a constant (which no run changes). bind may
     be NULL (nothing bound); param_structural may be
     NULL (none structural). */
  ldae_outputs_fn bind;
  int n_bound_params;
  const int *bound_params;             /* n_bound_params */
  int n_bound_starts;
  const int *bound_starts;             /* n_bound_starts: unknown indices */
  int bind_passes;
  const int *param_structural;         /* n_params */

  /* ---- Dynamic state selection of large blocks (ABI 8) ----
     p holds n_selection entries past the discrete values' pre() values:
     the selection matrices of the dynamic sets. */
  int n_dynamic_sets;
  const ldae_dynamic_set *dynamic_sets;
  int n_selection;

  /* ---- The model as written, for the geometric methods (ABI 9) ----
     --method sga|ode integrate the SGA's vector field, whose rows are not
     the model's equations, so the pencil an event's re-initialization
     jumps along (seed 002's rule, T(E, F)) comes from here: the
     n_written rows of written_residual are every equation of the model
     and the link rows der(slot) - next slot, over the same unknowns;
     written_jacobian writes dF/dy and dF/dy' of them (dense,
     column-major n_written x n). 0 and NULL for the other methods and for
     models without events. */
  int n_written;
  ldae_init_residual_fn written_residual;
  ldae_init_jacobian_fn written_jacobian;

  /* ---- Modes compiled ahead (ABI 12) ----
     A variable-structure model (n_mode > 0) run without a compiler (the
     program of --emit c): mode_models[j] is the model of the mode whose
     values (mode_discrete order) are mode_model_values[j * n_mode + i].
     When an event enters a mode, the run looks it up here if it has no
     mode provider; a mode not listed ends the run (status 3). 0 and NULL
     when the modes are compiled as a run reaches them (ldaec). */
  int n_mode_models;
  const double *mode_model_values;       /* n_mode_models * n_mode */
  const struct ldae_model *const *mode_models; /* n_mode_models */
} ldae_model;

/* Models with n <= LDAE_DENSE_THRESHOLD unknowns use the dense Jacobians
   (state_sets[i].jacobian_dense and init_jacobian, filled by every code
   generator); above it those are NULL and the runtime uses jacobian_csc
   and init_jacobian_csc with KLU. The CSC patterns and functions are
   always present. */
#define LDAE_DENSE_THRESHOLD 32

#ifdef __cplusplus
}
#endif

#endif /* LDAE_MODEL_H */
