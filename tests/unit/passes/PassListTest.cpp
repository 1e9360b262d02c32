// The pass list (Passes.def) against what uses it: each create function
// makes the pass of its own entry, every method's pipeline runs passes in
// table order and reads only results an earlier pass produced, and the
// driver's --print-after accepts exactly the table's names.
#include "passes/Passes.h"
#include "passes/Results.h"

#include <gtest/gtest.h>

#include <algorithm>

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <functional>
#include <set>
#include <string>
#include <typeindex>

using namespace ldae;
using passes::Method;

namespace {

struct Entry {
  const char *name;
  std::function<std::unique_ptr<passes::Pass>()> create;
};

const std::vector<Entry> &entries() {
  static const std::vector<Entry> table = {
#define PASS(Id, Name, Summary, Create) {Name, [] { return passes::Create(); }},
#include "passes/Passes.def"
  };
  return table;
}

std::vector<std::string> namesOf(const passes::PassPipeline &p) {
  std::vector<std::string> out;
  for (const auto &pass : p)
    out.push_back(pass->name());
  return out;
}

constexpr std::array<Method, 4> kMethods = {
    Method::DummyDerivatives, Method::Sga, Method::Ode, Method::Raw};

/// Runs `command` (stderr merged), returns the exit code and the output.
std::pair<int, std::string> runCommand(const std::string &command) {
  std::string out;
  FILE *p = popen((command + " 2>&1").c_str(), "r");
  if (!p)
    return {-1, ""};
  std::array<char, 4096> buf;
  size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), p)) > 0)
    out.append(buf.data(), n);
  int status = pclose(p);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

} // namespace

TEST(PassList, EachCreateFunctionMakesItsOwnEntry) {
  const std::vector<passes::PassInfo> &list = passes::passList();
  ASSERT_EQ(list.size(), entries().size());
  std::set<std::string> seen;
  for (size_t i = 0; i < list.size(); ++i) {
    EXPECT_EQ(std::string(list[i].name), entries()[i].name);
    EXPECT_TRUE(seen.insert(list[i].name).second) << list[i].name;
    EXPECT_NE(std::string(list[i].summary), "");
    std::unique_ptr<passes::Pass> pass = entries()[i].create();
    EXPECT_EQ(std::string(pass->name()), list[i].name);
    EXPECT_EQ(static_cast<size_t>(pass->id()), i);
  }
}

TEST(PassList, PipelinesRunInTableOrderOnResultsProducedBefore) {
  const std::vector<passes::PassInfo> &list = passes::passList();
  for (Method m : kMethods) {
    passes::PassPipeline p = passes::pipelineFor(m);
    ASSERT_FALSE(p.empty());
    size_t lastId = 0;
    std::set<std::type_index> produced;
    for (const auto &pass : p) {
      size_t id = static_cast<size_t>(pass->id());
      EXPECT_TRUE(&pass == &p.front() || id > lastId)
          << pass->name() << " out of table order in "
          << passes::methodSpelling(m);
      lastId = id;
      for (std::type_index t : pass->reads())
        EXPECT_TRUE(produced.count(t))
            << pass->name() << " reads " << t.name()
            << " before any pass produced it in "
            << passes::methodSpelling(m);
      for (std::type_index t : pass->produces())
        produced.insert(t);
      EXPECT_LT(id, list.size());
    }
    // Every method ends with the index-1 system.
    EXPECT_TRUE(produced.count(typeid(ir::DaeSystem)));
  }
}

TEST(PassList, MethodPipelines) {
  std::vector<std::string> dd = namesOf(passes::pipelineFor(Method::DummyDerivatives));
  // Every method sees the continuous system only: events runs first.
  EXPECT_EQ(dd, (std::vector<std::string>{
                    "events", "formal-index", "linear", "sga", "alias", "matching", "dm",
                    "pantelides", "dummy-derivatives", "build-system",
                    "sga-check", "blt", "prune", "causalize", "init"}));
  // sga and ode: the vector field on P_f, no structural index reduction.
  const std::vector<std::string> geometric{"events", "formal-index",
                                           "linear", "sga", "sga-system"};
  EXPECT_EQ(namesOf(passes::pipelineFor(Method::Sga)), geometric);
  EXPECT_EQ(namesOf(passes::pipelineFor(Method::Ode)), geometric);
  EXPECT_EQ(namesOf(passes::pipelineFor(Method::Raw)),
            (std::vector<std::string>{"events", "formal-index", "alias",
                                      "matching", "dm",
                                      "pantelides", "dummy-derivatives",
                                      "build-system", "blt"}));
}

TEST(PassList, MethodSpellings) {
  for (Method m : kMethods)
    EXPECT_EQ(passes::parseMethod(passes::methodSpelling(m)), m);
  EXPECT_EQ(passes::parseMethod("dd"), Method::DummyDerivatives);
  EXPECT_EQ(passes::parseMethod("raw"), Method::Raw);
  EXPECT_FALSE(passes::parseMethod("DD"));
  EXPECT_FALSE(passes::parseMethod(""));
}

// The driver validates --print-after against the same table: every name is
// accepted (and printed after), an unknown one exits 2 listing them all.
TEST(PassList, DriverPrintAfterAcceptsExactlyTheTable) {
  const std::string ldaec = LDAEC_BINARY;
  const std::string model = std::string(LDAEC_EXAMPLES) + "/pendulum.lsd";
  std::string all;
  const std::vector<std::string> dd =
      namesOf(passes::pipelineFor(Method::DummyDerivatives));
  for (const passes::PassInfo &p : passes::passList()) {
    all += std::string(all.empty() ? "" : ", ") + p.name;
    // A pass of another method's pipeline only (sga-system) prints there.
    const bool inDd = std::find(dd.begin(), dd.end(), p.name) != dd.end();
    auto [rc, out] = runCommand(ldaec + " " + model + " --analyze" +
                                (inDd ? "" : " --method sga") +
                                " --print-after " + p.name);
    EXPECT_EQ(rc, 0) << p.name << "\n" << out;
    EXPECT_NE(out.find(std::string("// ---- after ") + p.name + " ----"),
              std::string::npos)
        << p.name << "\n" << out;
  }
  auto [rc, out] =
      runCommand(ldaec + " " + model + " --analyze --print-after pantelidez");
  EXPECT_EQ(rc, 2) << out;
  EXPECT_EQ(out, "ldaec: error: unknown pass 'pantelidez' for --print-after; "
                 "the passes are: " +
                     all + "\n");
}
