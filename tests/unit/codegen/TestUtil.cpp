// Helpers of the codegen tests; see TestUtil.h.
#include "TestUtil.h"

#include <cmath>
#include <cstdlib>
#include <dlfcn.h>
#include <filesystem>
#include <fstream>
#include <gtest/gtest.h>
#include <random>
#include <sstream>
#include <tuple>
#include <type_traits>

namespace ldae::codegen::testing {

Evaluation evaluateAll(const ldae_model &m, const Point &pt) {
  Evaluation ev;
  const double *y = pt.y.data(), *yp = pt.yp.data(), *p = pt.p.data();
  auto add = [&](std::string label, size_t size, auto call) {
    std::vector<double> out(size + 1, -12345.0);
    ev.codes.push_back(call(out.data()));
    out.pop_back();
    ev.labels.push_back(std::move(label));
    ev.arrays.push_back(std::move(out));
  };
  for (int s = 0; s < m.n_state_sets; ++s) {
    const ldae_state_set &set = m.state_sets[s];
    std::string tag = std::to_string(s);
    add("residual " + tag, m.n,
        [&](double *o) { return set.residual(pt.t, y, yp, p, o); });
    add("jac_csc " + tag, set.jac_nnz, [&](double *o) {
      return set.jacobian_csc(pt.t, y, yp, p, pt.cj, o);
    });
    if (set.jacobian_dense)
      add("jac_dense " + tag, size_t(m.n) * m.n, [&](double *o) {
        return set.jacobian_dense(pt.t, y, yp, p, pt.cj, o);
      });
    if (set.pivot)
      add("pivot " + tag, size_t(set.pivot_size) * set.pivot_size,
          [&](double *o) { return set.pivot(pt.t, y, yp, p, o); });
  }
  add("init_residual", m.n_init,
      [&](double *o) { return m.init_residual(pt.t, y, yp, p, o); });
  size_t nj = size_t(m.n_init) * m.n;
  if (m.init_jacobian)
    add("init_jacobian", 2 * nj, [&](double *o) {
      return m.init_jacobian(pt.t, y, yp, p, o, o + nj);
    });
  size_t nz = m.init_jac_nnz;
  add("init_jac_csc", 2 * nz, [&](double *o) {
    return m.init_jacobian_csc(pt.t, y, yp, p, o, o + nz);
  });
  add("roots", m.n_roots, [&](double *o) { return m.roots(pt.t, y, yp, p, o); });
  add("outputs", m.n_outputs,
      [&](double *o) { return m.outputs(pt.t, y, yp, p, o); });
  add("drift", m.n_drift, [&](double *o) { return m.drift(pt.t, y, yp, p, o); });
  if (m.constraints)
    add("constraints", m.n_constraints,
        [&](double *o) { return m.constraints(pt.t, y, p, o); });
  if (m.constraint_jacobian)
    add("constraint_jacobian", size_t(m.n_constraints) * m.n,
        [&](double *o) { return m.constraint_jacobian(pt.t, y, p, o); });
  if (m.event_update)
    add("event_update", size_t(m.n_discrete) + 2 * m.n_reinit + m.n_terminate,
        [&](double *o) { return m.event_update(pt.t, y, yp, p, o); });
  if (m.time_events)
    add("time_events", size_t(m.n_time_thresholds) + 2 * m.n_samples,
        [&](double *o) { return m.time_events(pt.t, y, yp, p, o); });
  if (m.asserts)
    add("asserts", m.n_asserts,
        [&](double *o) { return m.asserts(pt.t, y, yp, p, o); });
  return ev;
}

std::string compareEvaluations(const Evaluation &a, const Evaluation &b,
                               double rel) {
  if (a.labels != b.labels)
    return "different function lists";
  std::ostringstream os;
  os.precision(17);
  for (size_t i = 0; i < a.arrays.size(); ++i) {
    if (a.codes[i] != b.codes[i]) {
      os << a.labels[i] << ": return code " << a.codes[i] << " vs "
         << b.codes[i];
      return os.str();
    }
    if (a.codes[i] != 0)
      continue; // outputs are unspecified after an error
    for (size_t k = 0; k < a.arrays[i].size(); ++k) {
      double x = a.arrays[i][k], y = b.arrays[i][k];
      if (!(std::fabs(x - y) <= rel * std::max(std::fabs(x), std::fabs(y)))) {
        os << a.labels[i] << "[" << k << "]: " << x << " vs " << y;
        return os.str();
      }
    }
  }
  return "";
}

namespace {

/// The tables of the events block (ABI 6): equal, and NULL exactly where
/// their count is 0.
std::string compareEventMetadata(const ldae_model &a, const ldae_model &b) {
  std::ostringstream os;
  auto check = [&](bool ok, const std::string &what) {
    if (!ok && os.str().empty())
      os << "event metadata differs: " << what;
  };
  check(a.n_discrete == b.n_discrete && a.n_reinit == b.n_reinit &&
            a.n_terminate == b.n_terminate &&
            a.n_time_thresholds == b.n_time_thresholds &&
            a.n_samples == b.n_samples && a.n_asserts == b.n_asserts &&
            a.n_mode == b.n_mode,
        "counts");
  if (!os.str().empty())
    return os.str();
  auto table = [&](const auto *x, const auto *y, int count,
                   const std::string &what) {
    check((x == nullptr) == (count == 0) && (y == nullptr) == (count == 0),
          what + " is NULL where it should not be, or the reverse");
    for (int i = 0; i < count && x && y; ++i) {
      if constexpr (std::is_same_v<decltype(x), const char *const *>)
        check(std::string(x[i]) == y[i], what);
      else
        check(x[i] == y[i], what);
    }
  };
  table(a.discrete_names, b.discrete_names, a.n_discrete, "discrete_names");
  table(a.discrete_start, b.discrete_start, a.n_discrete, "discrete_start");
  table(a.discrete_kind, b.discrete_kind, a.n_discrete, "discrete_kind");
  table(a.root_relation, b.root_relation, a.n_discrete ? a.n_roots : 0,
        "root_relation");
  table(a.reinit_target, b.reinit_target, a.n_reinit, "reinit_target");
  table(a.terminate_message, b.terminate_message, a.n_terminate,
        "terminate_message");
  table(a.threshold_relation, b.threshold_relation, a.n_time_thresholds,
        "threshold_relation");
  table(a.sample_discrete, b.sample_discrete, a.n_samples, "sample_discrete");
  table(a.assert_message, b.assert_message, a.n_asserts, "assert_message");
  table(a.assert_level, b.assert_level, a.n_asserts, "assert_level");
  table(a.assert_origin, b.assert_origin, a.n_asserts, "assert_origin");
  table(a.mode_discrete, b.mode_discrete, a.n_mode, "mode_discrete");
  table(a.mode_values, b.mode_values, a.n_mode, "mode_values");
  check(!a.event_update == !b.event_update && !a.time_events == !b.time_events &&
            !a.asserts == !b.asserts,
        "event functions");
  for (auto [x, y, what] : {std::tuple{a.dummy_of, b.dummy_of, "dummy_of"},
                            {a.original_row, b.original_row, "original_row"}}) {
    check(!x == !y, what);
    for (int s = 0; x && y && s < a.n_state_sets; ++s)
      for (int i = 0; i < a.n; ++i)
        check(x[s][i] == y[s][i], what);
  }
  return os.str();
}

} // namespace

std::string compareMetadata(const ldae_model &a, const ldae_model &b) {
  std::ostringstream os;
  auto check = [&](bool ok, const char *what) {
    if (!ok && os.str().empty())
      os << "metadata differs: " << what;
  };
  check(a.abi_version == b.abi_version, "abi_version");
  check(std::string(a.name) == b.name, "name");
  check(a.n == b.n && a.n_params == b.n_params &&
            a.n_state_sets == b.n_state_sets && a.n_init == b.n_init &&
            a.n_roots == b.n_roots && a.n_outputs == b.n_outputs &&
            a.n_drift == b.n_drift && a.init_jac_nnz == b.init_jac_nnz &&
            a.n_ode == b.n_ode && a.n_constraints == b.n_constraints &&
            a.project_constraints == b.project_constraints &&
            !a.init_jacobian == !b.init_jacobian,
        "sizes");
  if (!os.str().empty())
    return os.str();
  for (int i = 0; i < a.n; ++i) {
    check(std::string(a.var_names[i]) == b.var_names[i], "var_names");
    check(a.start_y[i] == b.start_y[i] && a.start_yp[i] == b.start_yp[i] &&
              a.nominal[i] == b.nominal[i] && a.fixed[i] == b.fixed[i],
          "start values");
  }
  for (int i = 0; i < a.n_params; ++i)
    check(std::string(a.param_names[i]) == b.param_names[i] &&
              a.param_values[i] == b.param_values[i],
          "parameters");
  for (int i = 0; i < a.n_outputs; ++i)
    check(std::string(a.output_names[i]) == b.output_names[i], "outputs");
  for (int s = 0; s < a.n_state_sets; ++s) {
    const ldae_state_set &x = a.state_sets[s], &y = b.state_sets[s];
    check(x.jac_nnz == y.jac_nnz && x.pivot_size == y.pivot_size &&
              std::string(x.description) == y.description &&
              !x.jacobian_dense == !y.jacobian_dense,
          "state set");
    if (!os.str().empty())
      break;
    for (int i = 0; i < a.n; ++i)
      check(x.is_differential[i] == y.is_differential[i], "is_differential");
    for (int i = 0; i <= a.n; ++i)
      check(x.jac_colptr[i] == y.jac_colptr[i], "colptr");
    for (int i = 0; i < x.jac_nnz; ++i)
      check(x.jac_rowind[i] == y.jac_rowind[i], "rowind");
  }
  for (int i = 0; i <= a.n; ++i)
    check(a.init_jac_colptr[i] == b.init_jac_colptr[i], "init colptr");
  for (int i = 0; i < a.init_jac_nnz; ++i)
    check(a.init_jac_rowind[i] == b.init_jac_rowind[i], "init rowind");
  auto same = [](double u, double v) {
    return u == v || (std::isnan(u) && std::isnan(v));
  };
  if (os.str().empty())
    os << compareEventMetadata(a, b);
  check(same(a.start_time, b.start_time) && same(a.stop_time, b.stop_time) &&
            same(a.tolerance, b.tolerance) && same(a.interval, b.interval),
        "experiment");
  return os.str();
}

std::vector<double> parameterVector(const ldae_model &m) {
  std::vector<double> p(m.param_values, m.param_values + m.n_params);
  for (int copy = 0; copy < 2; ++copy)
    p.insert(p.end(), m.discrete_start, m.discrete_start + m.n_discrete);
  return p;
}

Point randomPoint(const ldae_model &m, unsigned seed, double lo, double hi) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> d(lo, hi);
  Point pt;
  pt.t = d(rng);
  pt.cj = std::uniform_real_distribution<double>(0.5, 50)(rng);
  for (int i = 0; i < m.n; ++i) {
    pt.y.push_back(d(rng));
    pt.yp.push_back(d(rng));
  }
  pt.p = parameterVector(m);
  // Discrete values (and pre() values) 0 or 1, so both branches of what
  // reads them are taken.
  for (size_t k = m.n_params; k < pt.p.size(); ++k)
    pt.p[k] = rng() % 2;
  return pt;
}

int run(const std::string &command) {
  int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string makeTempDir(const std::string &stem) {
  // In the test's working directory (the build tree), not the system
  // temporary directory, and removed when the test binary exits: a test
  // run leaves no files behind.
  struct Created {
    std::vector<std::filesystem::path> dirs;
    ~Created() {
      std::error_code ec;
      for (const auto &d : dirs)
        std::filesystem::remove_all(d, ec);
    }
  };
  static Created created;
  static int counter = 0;
  std::filesystem::path dir =
      std::filesystem::current_path() /
      ("ldae_cg_" + stem + "_" + std::to_string(getpid()) + "_" +
       std::to_string(counter++));
  std::filesystem::create_directories(dir);
  created.dirs.push_back(dir);
  return dir.string();
}

CLibrary::CLibrary(const ir::DaeSystem &sys, const CodegenOptions &opts) {
  auto text = emitC(sys, false, opts);
  if (!text) {
    error_ = text.error();
    return;
  }
  std::string dir = makeTempDir("lib");
  std::ofstream(dir + "/model.c") << *text;
  std::string cmd = "cc -std=c99 -O2 -Wall -Werror -shared -fPIC -o " + dir +
                    "/model.so " + dir + "/model.c -lm 2> " + dir + "/cc.log";
  if (run(cmd) != 0) {
    std::ifstream log(dir + "/cc.log");
    error_ = "cc failed: " + std::string(std::istreambuf_iterator<char>(log), {})
                                 .substr(0, 2000);
    return;
  }
  handle_ = dlopen((dir + "/model.so").c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle_) {
    error_ = dlerror();
    return;
  }
  using GetModel = const ldae_model *(*)();
  auto get = reinterpret_cast<GetModel>(dlsym(handle_, "ldae_get_model"));
  if (!get) {
    error_ = "no ldae_get_model";
    return;
  }
  model_ = get();
}

CLibrary::~CLibrary() {
  if (handle_)
    dlclose(handle_);
}

std::unique_ptr<CompiledModel> compileOrDie(const ir::DaeSystem &sys,
                                            const CodegenOptions &opts) {
  auto m = compile(sys, opts);
  if (!m) {
    ADD_FAILURE() << "compile failed: " << m.error();
    return nullptr;
  }
  return std::move(*m);
}

} // namespace ldae::codegen::testing
