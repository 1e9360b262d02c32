// Mutation fuzzing of the whole frontend, in process: the examples, the
// language tests and the library, corrupted at random (characters and
// tokens deleted, inserted, swapped, duplicated; keywords and huge numbers
// inserted) with a fixed seed. Every run must end normally: a model, or
// errors reported; never a crash, an escaped exception or a hang.
#include "Corpus.h"
#include "frontend/Frontend.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

using namespace ldae;

namespace {

std::vector<std::string> readCorpus() {
  return readTestCorpus({"/examples", "/tests/lang/frontend", "/stdlib"});
}

const char *const kSnippets[] = {
    "end ", "model ", "for ", "if ", "then ", "loop ", "connect(", "der(",
    "extends ", "(", ")", "[", "]", "{", "}", ";", ",", "=", ":=", ".",
    "'", "\"", "/*", "//", "when ", "function ", "each ", "parameter ",
    "1e308", "100000000", "-1", "0", ":", "end for;", "end if;", "x", "pre(",
    "sum(", " for i in 1:3", "algorithm ", "Real ", "flow ", "package ",
    "import ", "annotation(", "size(", "@", "\n",
};

class Mutator {
public:
  explicit Mutator(uint32_t seed) : rng_(seed) {}

  std::string mutate(std::string s) {
    int n = 1 + pick(4);
    for (int k = 0; k < n; ++k) {
      if (s.empty()) {
        s = kSnippets[pick(std::size(kSnippets))];
        continue;
      }
      size_t at = pick(s.size());
      switch (pick(7)) {
      case 0: // delete a character
        s.erase(at, 1);
        break;
      case 1: // insert a character
        s.insert(at, 1, " ;(){}[]=+-*/^.,:'\"0123456789abxyz\n"[pick(36)]);
        break;
      case 2: { // swap two characters
        size_t b = pick(s.size());
        std::swap(s[at], s[b]);
        break;
      }
      case 3: { // delete a token
        auto [b, e] = tokenAt(s, at);
        s.erase(b, e - b);
        break;
      }
      case 4: { // duplicate a token elsewhere
        auto [b, e] = tokenAt(s, at);
        std::string tok = s.substr(b, e - b);
        s.insert(pick(s.size()), tok);
        break;
      }
      case 5: // insert a keyword or punctuation
        s.insert(at, kSnippets[pick(std::size(kSnippets))]);
        break;
      default: { // swap two tokens
        auto [b1, e1] = tokenAt(s, at);
        auto [b2, e2] = tokenAt(s, pick(s.size()));
        if (e1 <= b2) {
          std::string t1 = s.substr(b1, e1 - b1), t2 = s.substr(b2, e2 - b2);
          s.replace(b2, e2 - b2, t1);
          s.replace(b1, e1 - b1, t2);
        }
        break;
      }
      }
    }
    return s;
  }

private:
  size_t pick(size_t n) { return std::uniform_int_distribution<size_t>(0, n - 1)(rng_); }

  static bool word(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }
  /// The token around `at`: a word, or one other character.
  static std::pair<size_t, size_t> tokenAt(const std::string &s, size_t at) {
    if (!word(s[at]))
      return {at, at + 1};
    size_t b = at, e = at;
    while (b > 0 && word(s[b - 1]))
      --b;
    while (e < s.size() && word(s[e]))
      ++e;
    return {b, e};
  }

  std::mt19937 rng_;
};

} // namespace

TEST(FrontendFuzz, TenThousandCorruptedModels) {
  std::vector<std::string> corpus = readCorpus();
  ASSERT_GE(corpus.size(), 20u);
  // LDAE_FUZZ_SEED / LDAE_FUZZ_ITERS explore further by hand; CI uses the
  // fixed defaults.
  const char *seedEnv = std::getenv("LDAE_FUZZ_SEED");
  const char *itersEnv = std::getenv("LDAE_FUZZ_ITERS");
  Mutator mutator(seedEnv ? static_cast<uint32_t>(std::atoi(seedEnv)) : 20261122);
  int iterations = itersEnv ? std::atoi(itersEnv) : 10000;
  frontend::FrontendOptions opts;
  opts.libraryPaths = {std::string(LDAE_SOURCE_DIR) + "/stdlib"};
  size_t models = 0, rejected = 0;
  double slowest = 0;
  for (int iter = 0; iter < iterations; ++iter) {
    std::string text = mutator.mutate(corpus[iter % corpus.size()]);
    SourceManager sources;
    DiagnosticEngine diags(sources);
    auto start = std::chrono::steady_clock::now();
    std::unique_ptr<ir::Model> model;
    try {
      model = frontend::compileSource("fuzz.lsd", text, opts, sources, diags);
      if (model) {
        frontend::checkBalance(*model, diags);
        (void)model->print();
      }
      for (const Diagnostic &d : diags.diagnostics())
        (void)diags.render(d);
    } catch (...) {
      FAIL() << "exception escaped the frontend on input:\n" << text;
    }
    double secs = std::chrono::duration<double>(
                      std::chrono::steady_clock::now() - start)
                      .count();
    slowest = std::max(slowest, secs);
    ASSERT_LT(secs, 5.0) << "frontend too slow on input:\n" << text;
    if (model) {
      ++models;
    } else {
      ++rejected;
      ASSERT_TRUE(diags.hasErrors()) << "rejected without an error:\n" << text;
    }
  }
  // Both outcomes occur: the corpus is valid, the corruption breaks most.
  EXPECT_GT(models, static_cast<size_t>(iterations) / 100);
  EXPECT_GT(rejected, static_cast<size_t>(iterations) / 10);
  std::cout << "fuzz: " << models << " flattened, " << rejected
            << " rejected, slowest " << slowest << " s\n";
}
