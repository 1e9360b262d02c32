// Hopcroft–Karp with an explicit stack: models of 10^5 equations form long
// alternating chains, deeper than the C++ call stack allows.
#include "graph/Matching.h"

#include <limits>

namespace ldae::graph {

std::vector<std::vector<int>> BipartiteGraph::columns() const {
  std::vector<std::vector<int>> cols(numCols);
  for (int r = 0; r < numRows(); ++r)
    for (int c : rows[r])
      cols[c].push_back(r);
  return cols;
}

namespace {
constexpr int kInf = std::numeric_limits<int>::max();

class HopcroftKarp {
public:
  HopcroftKarp(const BipartiteGraph &g, const std::vector<char> &allowed,
               Matching &m)
      : g_(g), allowed_(allowed), m_(m), dist_(g.numRows()),
        next_(g.numRows()) {}

  void run() {
    greedy();
    while (layer())
      for (int r = 0; r < g_.numRows(); ++r)
        if (m_.rowMate[r] < 0 && dist_[r] == 0)
          augment(r);
  }

private:
  bool usable(int c) const { return allowed_.empty() || allowed_[c]; }

  // A cheap first pass: most equations have a free unknown of their own.
  void greedy() {
    for (int r = 0; r < g_.numRows(); ++r) {
      if (m_.rowMate[r] >= 0)
        continue;
      for (int c : g_.rows[r])
        if (usable(c) && m_.colMate[c] < 0) {
          m_.match(r, c);
          break;
        }
    }
  }

  // BFS from the free rows; true if some free column is reachable.
  bool layer() {
    std::vector<int> queue;
    for (int r = 0; r < g_.numRows(); ++r) {
      next_[r] = 0;
      if (m_.rowMate[r] < 0) {
        dist_[r] = 0;
        queue.push_back(r);
      } else {
        dist_[r] = kInf;
      }
    }
    bool found = false;
    for (size_t q = 0; q < queue.size(); ++q) {
      int r = queue[q];
      for (int c : g_.rows[r]) {
        if (!usable(c))
          continue;
        int w = m_.colMate[c];
        if (w < 0)
          found = true;
        else if (dist_[w] == kInf) {
          dist_[w] = dist_[r] + 1;
          queue.push_back(w);
        }
      }
    }
    return found;
  }

  // Iterative DFS along the layers; `next_[r]` is the edge row r tries next.
  bool augment(int root) {
    stack_.clear();
    stack_.push_back(root);
    while (!stack_.empty()) {
      int r = stack_.back();
      const std::vector<int> &adj = g_.rows[r];
      if (next_[r] == static_cast<int>(adj.size())) {
        dist_[r] = kInf; // dead end for the rest of this phase
        stack_.pop_back();
        continue;
      }
      int c = adj[next_[r]];
      if (!usable(c)) {
        ++next_[r];
        continue;
      }
      int w = m_.colMate[c];
      if (w < 0) {
        for (int s : stack_)
          m_.match(s, g_.rows[s][next_[s]]);
        return true;
      }
      if (dist_[w] != kInf && dist_[w] == dist_[r] + 1)
        stack_.push_back(w);
      else
        ++next_[r];
    }
    return false;
  }

  const BipartiteGraph &g_;
  const std::vector<char> &allowed_;
  Matching &m_;
  std::vector<int> dist_, next_, stack_;
};
} // namespace

Matching maximumMatching(const BipartiteGraph &g,
                         const std::vector<char> &colAllowed,
                         const Matching *initial) {
  Matching m = initial ? *initial : Matching(g.numRows(), g.numCols);
  m.rowMate.resize(g.numRows(), -1);
  m.colMate.resize(g.numCols, -1);
  HopcroftKarp(g, colAllowed, m).run();
  return m;
}

} // namespace ldae::graph
