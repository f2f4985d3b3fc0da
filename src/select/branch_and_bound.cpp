// Branch and bound for maximum coverage with n sensors on the Lagrangian bound (issue 14).
//
// A node fixes some candidates in (their cells count, their elements get weight 0) and removes
// others; the rest are free. Its bound is L of the Lagrangian relaxation over the free rows and
// the node's own elements (those of weight > 0 that a free row sees: any other element has
// y_e <= 0 at the node, so dropping it keeps the node's optimum and makes L no larger, and each
// pass touches fewer elements), at the parent's multipliers improved by a pass of exact
// coordinate descent (a node's own subgradient steps converge too slowly: at multi_bin_picking
// N = 8 five of them left L about 90 cells above the node's LP on average, and one pass of
// descent removes about a third of that for the cost of two steps). A dive
// child's problem is built from its parent's rows (the same problem, in one pass over shorter
// rows). At the root the steps start from the start multipliers and run in rounds of
// kRootChunk, Lagrangian fixing shrinking the problem between rounds, then CLP's LP relaxation
// warm-started from them (lp_bound.hpp). A node whose bound is not above the incumbent is
// pruned, otherwise Lagrangian fixing settles the candidates it can (repeatedly, while it
// changes something) and the node branches on the chosen row closest to being fixed in: first
// with it in, then without it (best bound first, plunging while the "in" child is the best). The Lagrangian subproblem's rows complete every
// node's fixed candidates into an answer, which improves the incumbent when it covers more (and
// then local search from it). The search is sequential; only the largest passes over the rows
// run on TBB's threads (ForEachRow), each row summed by one thread in element order, so the same
// input and stopping point give the same answer whatever the thread count. Each subtree returns
// an upper bound on what it holds, so stopping at the time limit still leaves a proof: the
// largest bound of the subtrees not finished. Rows go to the Lagrangian as runs of consecutive
// elements where that shortens the passes (kRunsFactor).
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>
#include <optional>
#include <queue>
#include <span>
#include <utility>

#include "select/lp_bound.hpp"
#include "select/methods.hpp"
#include "vantage/error.hpp"
#include "vantage/interrupt.hpp"

namespace vantage::detail {
namespace {

using Clock = std::chrono::steady_clock;

// Adds the seconds since `*since` to `*total` and moves `*since` to now.
void Lap(Clock::time_point* since, double* total) {
  const Clock::time_point now = Clock::now();
  *total += std::chrono::duration<double>(now - *since).count();
  *since = now;
}

// A node's multipliers: its parent's, improved by coordinate descent (CoordinateDescent), and how
// often fixing may re-bound one node. One pass of descent and no subgradient steps prove the most
// per second (bench/RESULTS.md, "Coordinate descent at the nodes": multi_bin_picking N = 9 in
// 15.2 CPU s and 15,195 nodes, where 5 steps and no descent took 99 s and 27,719 nodes; more
// passes or steps bound a node better and cost more than the nodes they save).
constexpr int kNodeDescentPasses = 1;
constexpr int kMaxFixingRounds = 2;
// CLP at the root needs time for at least this many passes over the rows (see RootRound).
constexpr double kMinLpPasses = 50;
// Rows go to the Lagrangian as runs of consecutive elements when that makes the passes this many
// times shorter (the generated 1,000 x 100,000 instance: 5.3 M nonzeros in 0.28 M runs; the
// 450-candidate worlds: 0.71 M in 0.33 M, left as they are).
constexpr size_t kRunsFactor = 2;
// The root's steps run in rounds of this many, with Lagrangian fixing between them.
constexpr int kRootChunk = 100;

struct Node {
  std::vector<uint32_t> fixed;    // candidates in
  std::vector<uint32_t> removed;  // candidates out
  std::vector<uint32_t> free;     // candidates still open, ascending
  std::vector<uint32_t> weights;  // per element; 0 once a fixed candidate covers it
  uint64_t base = 0;              // cells the fixed candidates cover
  std::vector<double> lambda;     // multipliers per element
};

// A node waiting in the queue: its parent's bound, what is fixed, and the parent's multipliers
// (shared by both children; null once the queue holds too many: the root's are used then).
struct Open {
  uint64_t bound = 0;
  long order = 0;  // creation order: ties go to the deeper, then the older node
  std::vector<uint32_t> fixed;
  std::vector<uint32_t> removed;
  std::shared_ptr<const std::vector<float>> lambda;
};

struct OpenLess {
  bool operator()(const Open& a, const Open& b) const {
    if (a.bound != b.bound) return a.bound < b.bound;
    if (a.fixed.size() + a.removed.size() != b.fixed.size() + b.removed.size())
      return a.fixed.size() + a.removed.size() < b.fixed.size() + b.removed.size();
    return a.order > b.order;
  }
};

class Search {
 public:
  Search(const CoverageMatrix& matrix, size_t n, std::vector<uint32_t> start, Clock::time_point end)
      : matrix_(matrix), n_(n), end_(end), best_(std::move(start)) {
    best_cells_ = matrix_.CoveredWeight(best_);
    // Multipliers kept in the queue: at most about kStoredMultiplierBytes of them.
    max_stored_ = std::max<size_t>(
        16, kStoredMultiplierBytes / (sizeof(float) * std::max<size_t>(1, matrix.element_count())));
  }

  // Best bound first, plunging: after a branch the "in" child is bounded next when no node in
  // the queue has a larger bound (a dive of at most n nodes, its rows built from its parent's),
  // and the "out" child waits in the queue. The largest bound in the queue (and of the dive) always bounds what is
  // left. Returns the bound on the optimum when the search ends (finished or out of time).
  uint64_t Run(uint64_t upper_bound) {
    std::priority_queue<Open, std::vector<Open>, OpenLess> queue;
    std::optional<Open> dive = Open{upper_bound, order_++, {}, {}, nullptr};
    while (dive || !queue.empty()) {
      ThrowIfInterrupted();
      if (dive && dive->bound <= best_cells_) dive.reset();
      if (!dive && (queue.empty() || queue.top().bound <= best_cells_)) break;  // all pruned
      if (Clock::now() >= end_ || nodes_ >= max_nodes_) {
        timed_out_ = true;
        uint64_t bound = best_cells_;
        if (dive) bound = std::max(bound, dive->bound);
        if (!queue.empty()) bound = std::max(bound, queue.top().bound);
        return bound;
      }
      Open open;
      // A dive child is its parent less the candidate branched on, fixed in: its problem comes
      // from the parent's rows, still in rows_ (the same problem as from the matrix, cheaper).
      from_parent_ = dive.has_value() && nodes_ > 0;  // the first dive is the root
      if (dive) {
        open = std::move(*dive);
        dive.reset();
      } else {
        open = queue.top();
        queue.pop();
      }
      Clock::time_point lap = Clock::now();
      Node node = Rebuild(open);
      Lap(&lap, &profile_.rebuild_seconds);
      const bool is_root = nodes_ == 0;
      ++nodes_;
      const std::optional<Branch> branch = Bound(&node, open.bound, is_root);
      if (!branch) continue;
      const auto [bound, pick, out_bound] = *branch;
      const uint32_t candidate = node.free[pick];
      parent_pick_ = pick;
      std::shared_ptr<const std::vector<float>> lambda;
      if (queue.size() < max_stored_) {
        lambda = std::make_shared<const std::vector<float>>(node.lambda.begin(), node.lambda.end());
      }
      dive = Open{bound, order_++, node.fixed, node.removed, lambda};
      dive->fixed.push_back(candidate);
      // Plunge only while the "in" child is also best first's choice; otherwise it waits too.
      // At the time limit the bound is the largest in the queue, and best first lowers that
      // fastest (multi_bin_picking_b, 9 s: N = 9 0.45 points instead of 0.49-0.53, N = 10 0.51
      // instead of 0.56-0.59).
      if (!queue.empty() && dive->bound < queue.top().bound) {
        queue.push(std::move(*dive));
        dive.reset();
      }
      if (out_bound <= best_cells_) continue;  // the "out" child is pruned already
      Open out{out_bound, order_++, std::move(node.fixed), std::move(node.removed), lambda};
      out.removed.push_back(candidate);
      queue.push(std::move(out));
    }
    return best_cells_;
  }

  void set_max_nodes(long nodes) { max_nodes_ = nodes; }
  void set_root_budget(int steps, double seconds, bool lp) {
    root_steps_limit_ = steps;
    root_seconds_ = seconds;
    root_lp_ = lp;
  }
  const std::vector<uint32_t>& best() const { return best_; }
  const BranchAndBoundProfile& profile() const { return profile_; }
  uint64_t best_cells() const { return best_cells_; }
  long nodes() const { return nodes_; }
  bool timed_out() const { return timed_out_; }
  uint64_t root_bound() const { return root_bound_; }
  size_t root_fixed_in() const { return root_fixed_in_; }
  size_t root_removed() const { return root_removed_; }
  int root_steps() const { return root_steps_; }
  uint64_t root_subgradient_bound() const { return root_sg_bound_; }
  uint64_t root_lp_bound() const { return root_lp_bound_; }
  double root_lp_seconds() const { return root_lp_seconds_; }
  bool root_lp_optimal() const { return root_lp_optimal_; }
  bool root_lp_improved() const { return root_lp_improved_; }

 private:
  static constexpr size_t kStoredMultiplierBytes = size_t{256} << 20;

  // The node of `open`: free candidates, weights left, and its multipliers.
  Node Rebuild(const Open& open) const {
    Node node;
    node.removed = open.removed;
    node.weights.resize(matrix_.element_count());
    for (uint32_t e = 0; e < matrix_.element_count(); ++e) node.weights[e] = matrix_.Weight(e);
    std::vector<bool> settled(matrix_.candidate_count(), false);
    for (const uint32_t i : open.removed) settled[i] = true;
    for (const uint32_t i : open.fixed) {
      settled[i] = true;
      Fix(i, &node);
    }
    for (uint32_t i = 0; i < matrix_.candidate_count(); ++i) {
      if (!settled[i] && !matrix_.Row(i).empty()) node.free.push_back(i);
    }
    if (open.lambda) {
      node.lambda.assign(open.lambda->begin(), open.lambda->end());
    } else {
      node.lambda = root_lambda_;  // empty at the root: the start multipliers are set there
    }
    return node;
  }

  // What Bound leaves to branch on.
  struct Branch {
    uint64_t bound = 0;      // the node's
    size_t pick = 0;         // the free position to branch on
    uint64_t out_bound = 0;  // the "out" child's, at the node's multipliers
  };

  // Bounds `node` (at most `parent_bound`) and fixes what the bound settles, repeatedly; offers
  // the relaxation's answers as incumbents. Returns the node's bound and the free position to
  // branch on, or nothing when the node is closed (pruned, or nothing left to choose).
  std::optional<Branch> Bound(Node* node, uint64_t parent_bound, bool is_root) {
    uint64_t bound = parent_bound;
    std::vector<std::vector<uint32_t>>& rows = rows_;  // per free row, the node's elements in it
    std::vector<uint32_t>& elements = elements_;       // the node's -> the matrix's element
    std::vector<uint32_t> weights;                     // per node element
    std::vector<double> lambda;                        // per node element
    std::vector<uint32_t> kept;  // free positions of the round before still free
    if (node->lambda.empty()) node->lambda.assign(matrix_.element_count(), 0.0);
    ExactLagrangian exact;
    int rounds = 0;  // bounds made since the root's steps ended
    Clock::time_point lap = Clock::now();
    for (int round = 0;; ++round) {
      const size_t slots = n_ - node->fixed.size();
      if (slots == 0 || node->free.size() <= slots) {
        // Nothing left to choose: the fixed candidates, and all free ones if there is room.
        std::vector<uint32_t> all = node->fixed;
        if (slots > 0) all.insert(all.end(), node->free.begin(), node->free.end());
        Offer(std::move(all));
        return std::nullopt;
      }
      // The node's problem over its own elements: those of weight > 0 that a free row sees,
      // numbered in ascending order. An element no free row sees has y_e <= 0 here, so leaving
      // it out leaves the node's optimum unchanged, and L over the rest still bounds it. Round 0
      // reads the matrix's rows; later rounds the rows of the round before (fewer rows, and
      // the elements the newly fixed candidates cover gone).
      if (round == 0 && from_parent_) {
        kept.clear();
        for (uint32_t q = 0; q < problem_rows_; ++q) {
          if (q != parent_pick_) kept.push_back(q);
        }
        VANTAGE_CHECK(kept.size() == node->free.size());
      }
      if (round == 0 && !from_parent_) {
        BuildProblem(
            *node, node->free.size(), matrix_.element_count(),
            [&](size_t q) { return std::span<const uint32_t>(matrix_.Row(node->free[q])); },
            [](uint32_t e) { return e; }, &rows, &elements, &weights);
      } else {
        const std::vector<uint32_t> before = elements;
        BuildProblem(
            *node, kept.size(), before.size(),
            [&](size_t q) { return std::span<const uint32_t>(rows[kept[q]]); },
            [&](uint32_t k) { return before[k]; }, &rows, &elements, &weights);
      }
      const std::span<const std::vector<uint32_t>> problem_rows(rows.data(), problem_rows_);
      // Rows as runs of consecutive elements where that shortens the passes (decided once, at
      // the root: each run costs two entries, and the prefix sums a pass over the elements).
      if (is_root && round == 0) {
        size_t nonzeros = 0;
        size_t entries = 0;
        for (const std::vector<uint32_t>& row : problem_rows) {
          nonzeros += row.size();
          for (size_t j = 0; j < row.size(); ++j)
            entries += j == 0 || row[j] != row[j - 1] + 1 ? 2 : 0;
        }
        use_runs_ = kRunsFactor * (entries + elements.size()) < nonzeros;
        profile_.runs = use_runs_;
      }
      if (use_runs_) {
        runs_.resize(std::max(runs_.size(), problem_rows_));
        ForEachRow(problem_rows_, problem_rows_, [&](size_t begin, size_t end) {
          for (size_t q = begin; q < end; ++q) {
            runs_[q].clear();
            AppendRuns(rows[q], &runs_[q]);
          }
        });
      }
      const LagrangianProblem problem{
          problem_rows, weights, slots,
          use_runs_ ? std::span<const std::vector<uint32_t>>(runs_.data(), problem_rows_)
                    : std::span<const std::vector<uint32_t>>()};
      const uint64_t target = best_cells_ > node->base ? best_cells_ - node->base : 0;
      const double left = std::chrono::duration<double>(end_ - Clock::now()).count();
      Lap(&lap, &profile_.rows_seconds);
      if (is_root && round == 0) {
        lambda = StartMultipliers(problem);
      } else {
        lambda.resize(elements.size());
        for (size_t k = 0; k < elements.size(); ++k) lambda[k] = node->lambda[elements[k]];
      }
      if (is_root && !root_done_) {
        RootRound(problem, target, left, *node, round == 0, &lambda);
        Lap(&lap, &profile_.root_seconds);
      } else {
        CoordinateDescent(problem, kNodeDescentPasses, &lambda);
        Lap(&lap, &profile_.descent_seconds);
      }
      for (size_t k = 0; k < elements.size(); ++k) node->lambda[elements[k]] = lambda[k];
      if (is_root) root_lambda_ = node->lambda;
      exact = EvaluateExactly(problem, lambda);
      ++profile_.evaluations;
      Lap(&lap, &profile_.eval_seconds);
      bound = std::min(bound, node->base + (exact.scaled_value >> exact.bits));
      if (is_root) root_bound_ = bound;
      // The relaxation's answer completes the fixed candidates: a cheap incumbent.
      std::vector<uint32_t> completed = node->fixed;
      for (const uint32_t q : exact.chosen) completed.push_back(node->free[q]);
      Offer(std::move(completed));
      Lap(&lap, &profile_.offer_seconds);
      if (bound <= best_cells_) return std::nullopt;
      // Out of rounds or of time: branch on what is bounded (rows and exact match node->free).
      // The root's steps go on in rounds until their budget is spent, each on what fixing left.
      const bool root_steps_left = is_root && !root_done_;
      if (!root_steps_left) ++rounds;
      if (rounds >= kMaxFixingRounds || Clock::now() >= end_) break;
      const Fixing fixing = LagrangianFixing(problem, exact, best_cells_ + 1 - node->base);
      Lap(&lap, &profile_.fixing_seconds);
      if (fixing.fixed_in.empty() && fixing.removed.empty() && !root_steps_left) break;
      if (fixing.fixed_in.size() > slots) return std::nullopt;  // no answer here beats it
      if (is_root) {
        root_fixed_in_ += fixing.fixed_in.size();
        root_removed_ += fixing.removed.size();
      }
      std::vector<bool> drop(node->free.size(), false);
      for (const uint32_t q : fixing.removed) {
        drop[q] = true;
        node->removed.push_back(node->free[q]);
      }
      for (const uint32_t q : fixing.fixed_in) {
        drop[q] = true;
        Fix(node->free[q], node);
      }
      std::vector<uint32_t> still_free;
      kept.clear();
      for (size_t q = 0; q < node->free.size(); ++q) {
        if (drop[q]) continue;
        still_free.push_back(node->free[q]);
        kept.push_back(static_cast<uint32_t>(q));
      }
      node->free = std::move(still_free);
    }
    // Branch on the chosen row closest to being fixed in (the largest r: leaving it out lowers
    // L the most), so that its "out" child is the likeliest to be pruned at once.
    size_t pick = exact.chosen.front();
    for (const uint32_t q : exact.chosen) {
      if (exact.rows[q] > exact.rows[pick]) pick = q;
    }
    // The "out" child at these multipliers: L with x_pick = 0 forced, the (slots + 1)-th row in
    // its place (LagrangianFixing's test; rows and exact match node->free here, and more free rows
    // than slots are left, so that row exists). An upper bound on the child, in exact integers.
    const uint64_t out_scaled = exact.scaled_value - exact.rows[pick] + exact.next_row;
    const uint64_t out_bound = std::min(bound, node->base + (out_scaled >> exact.bits));
    return Branch{bound, pick, out_bound};
  }

  // The node's problem from `count` free rows, source(q) the q-th as ascending ids of a space of
  // `space` ids, id k being the matrix's element global(k) (global ascending in k): the rows over
  // the elements of weight > 0 in them, renumbered 0, 1, ... in ascending order (`elements`:
  // back to the matrix's; `weights`: theirs at the node).
  template <typename Source, typename Global>
  void BuildProblem(const Node& node,
                    size_t count,
                    size_t space,
                    Source source,
                    Global global,
                    std::vector<std::vector<uint32_t>>* rows,
                    std::vector<uint32_t>* elements,
                    std::vector<uint32_t>* weights) {
    size_t nonzeros = 0;
    for (size_t q = 0; q < count; ++q) nonzeros += source(q).size();
    // seen[k]: 1 when a row holds id k; then its new id + 1 if it has weight left (0: absent).
    // The weight is looked at once per id, not per nonzero: the marking pass has no branch.
    std::vector<uint32_t>& seen = seen_;
    seen.assign(space, 0u);
    ForEachRow(count, nonzeros, [&](size_t begin, size_t end) {
      for (size_t q = begin; q < end; ++q) {
        for (const uint32_t k : source(q)) {
          std::atomic_ref<uint32_t>(seen[k]).store(1u, std::memory_order_relaxed);
        }
      }
    });
    elements->clear();
    weights->clear();
    for (uint32_t k = 0; k < space; ++k) {
      if (seen[k] == 0) continue;
      if (node.weights[global(k)] == 0) {
        seen[k] = 0;
        continue;
      }
      elements->push_back(global(k));
      weights->push_back(node.weights[global(k)]);
      seen[k] = static_cast<uint32_t>(elements->size());
    }
    // Into the spare rows (their capacity kept from node to node), then swapped in.
    std::vector<std::vector<uint32_t>>& next = spare_rows_;
    next.resize(std::max(next.size(), count));
    ForEachRow(count, nonzeros, [&](size_t begin, size_t end) {
      for (size_t q = begin; q < end; ++q) {
        // Written without a branch (whether an element stays is hard to predict).
        const std::span<const uint32_t> in = source(q);
        std::vector<uint32_t>& out = next[q];
        out.resize(in.size());
        size_t kept = 0;
        for (const uint32_t k : in) {
          const uint32_t id = seen[k];
          out[kept] = id - 1;
          kept += id != 0 ? 1 : 0;
        }
        out.resize(kept);
      }
    });
    // Both keep all their rows (and capacity); only the first `count` are the problem's.
    rows->resize(std::max(rows->size(), next.size()));
    next.resize(rows->size());
    std::swap(*rows, next);
    problem_rows_ = count;
  }

  // One round of the root's multipliers: kRootChunk subgradient steps from `lambda` (the start
  // multipliers in the first round), continuing the step scale where the round before left it;
  // between rounds fixing shrinks the problem, so later steps cost less. Once the steps are
  // spent (or stop), CLP's LP relaxation warm-started from them (a values pass of primal simplex
  // from the feasible point they give), in what is left of the root's share of the time;
  // whichever proves the smaller L. The LP's x, rounded to its n largest, is offered as an
  // incumbent.
  void RootRound(const LagrangianProblem& problem,
                 uint64_t target,
                 double left,
                 const Node& node,
                 bool first,
                 std::vector<double>* lambda) {
    if (first) {
      root_start_ = Clock::now();
      root_limit_seconds_ = std::min(left, root_seconds_);
      root_scale_ = kStartStepScale;
    }
    const double elapsed = std::chrono::duration<double>(Clock::now() - root_start_).count();
    const int chunk = std::min(kRootChunk, root_steps_limit_ - root_steps_);
    const SubgradientResult steps = SubgradientSteps(
        problem, target, std::max(chunk, 0), root_scale_, root_limit_seconds_ - elapsed, lambda);
    root_steps_ += steps.iterations;
    root_scale_ = steps.scale;
    if (steps.iterations == chunk && root_steps_ < root_steps_limit_) return;  // more rounds
    root_done_ = true;
    const double root_seconds = root_limit_seconds_;
    const Clock::time_point root_start = root_start_;
    const ExactLagrangian subgradient = EvaluateExactly(problem, *lambda);
    root_sg_bound_ = node.base + (subgradient.scaled_value >> subgradient.bits);
    root_sg_seconds_ = std::chrono::duration<double>(Clock::now() - root_start).count();
    // Building CLP's model costs a few passes over the rows, outside CLP's time limit, and each
    // simplex iteration about one: with time for fewer than kMinLpPasses it is not started.
    const double lp_seconds = root_seconds - root_sg_seconds_;
    const double pass_seconds = root_sg_seconds_ / std::max(1, root_steps_);
    if (root_lp_ && lp_seconds > kMinLpPasses * pass_seconds &&
        subgradient.scaled_value >> subgradient.bits > target) {
      const Clock::time_point lp_start = Clock::now();
      ClpCoverageLp lp(problem);
      const double built = std::chrono::duration<double>(Clock::now() - lp_start).count();
      const ClpLpSolution solution = lp.Solve(lp_seconds - built, *lambda);
      root_lp_seconds_ = std::chrono::duration<double>(Clock::now() - lp_start).count();
      const ExactLagrangian exact = EvaluateExactly(problem, solution.lambda);
      root_lp_bound_ = node.base + (exact.scaled_value >> exact.bits);
      root_lp_optimal_ = solution.optimal;
      if (exact.scaled_value < subgradient.scaled_value) *lambda = solution.lambda;
      std::vector<uint32_t> order(solution.x.size());
      std::iota(order.begin(), order.end(), 0u);
      std::stable_sort(order.begin(), order.end(),
                       [&](uint32_t a, uint32_t b) { return solution.x[a] > solution.x[b]; });
      std::vector<uint32_t> rounded = node.fixed;
      for (size_t q = 0; q < order.size() && rounded.size() < n_; ++q) {
        if (solution.x[order[q]] > 1e-9) rounded.push_back(node.free[order[q]]);
      }
      const uint64_t before = best_cells_;
      Offer(std::move(rounded));
      root_lp_improved_ = best_cells_ > before;
    }
  }

  void Fix(uint32_t candidate, Node* node) const {
    node->fixed.push_back(candidate);
    for (const uint32_t e : matrix_.Row(candidate)) {
      node->base += node->weights[e];
      node->weights[e] = 0;
    }
  }

  // A better answer (at most n sensors) becomes the incumbent, improved by 1-swap local search
  // (2-swaps can take seconds on large instances) while time is left.
  void Offer(std::vector<uint32_t> chosen) {
    if (matrix_.CoveredWeight(chosen) <= best_cells_) return;
    chosen = GreedyComplete(CellScorer(matrix_), std::move(chosen), n_);
    LocalOptions options;
    options.two_swap = false;
    if (Clock::now() < end_) chosen = LocalSearch(CellScorer(matrix_), std::move(chosen), options);
    best_cells_ = matrix_.CoveredWeight(chosen);
    best_ = std::move(chosen);
  }

  const CoverageMatrix& matrix_;
  size_t n_;
  Clock::time_point end_;
  std::vector<uint32_t> best_;
  uint64_t best_cells_ = 0;
  size_t max_stored_ = 0;
  long order_ = 0;
  long nodes_ = 0;
  long max_nodes_ = std::numeric_limits<long>::max();
  bool timed_out_ = false;
  int root_steps_limit_ = 0;
  bool root_lp_ = true;
  double root_seconds_ = 0;
  int root_steps_ = 0;
  double root_lp_seconds_ = 0;
  uint64_t root_lp_bound_ = 0;  // 0: CLP not run
  bool root_lp_optimal_ = false;
  bool root_lp_improved_ = false;
  double root_sg_seconds_ = 0;
  uint64_t root_sg_bound_ = 0;
  std::vector<double> root_lambda_;
  bool root_done_ = false;  // the root's steps (and CLP) are over
  Clock::time_point root_start_;
  double root_limit_seconds_ = 0;
  double root_scale_ = 0;
  uint64_t root_bound_ = std::numeric_limits<uint64_t>::max();  // until the root is bounded
  size_t root_fixed_in_ = 0;
  size_t root_removed_ = 0;
  BranchAndBoundProfile profile_;
  // Bound's working rows and BuildProblem's scratch (kept to reuse their capacity).
  std::vector<std::vector<uint32_t>> rows_;
  std::vector<std::vector<uint32_t>> spare_rows_;
  size_t problem_rows_ = 0;
  std::vector<uint32_t> seen_;
  std::vector<uint32_t> elements_;           // of rows_
  std::vector<std::vector<uint32_t>> runs_;  // rows_ as runs (use_runs_)
  bool use_runs_ = false;
  bool from_parent_ = false;  // the node bounded next is the dive child of rows_'s node
  uint32_t parent_pick_ = 0;  // the free position that node branched on
};

}  // namespace

BranchAndBoundResult BranchAndBound(const CoverageMatrix& matrix,
                                    size_t n,
                                    const std::vector<uint32_t>& start,
                                    uint64_t upper_bound,
                                    const BranchAndBoundLimits& limits) {
  VANTAGE_CHECK(n >= 1 && n <= matrix.candidate_count() && start.size() == n);
  const Clock::time_point end =
      Clock::now() + std::chrono::duration_cast<Clock::duration>(
                         std::chrono::duration<double>(std::max(0.0, limits.seconds)));
  Search search(matrix, n, start, end);
  search.set_root_budget(limits.root_steps, limits.root_share * limits.seconds, limits.root_lp);
  search.set_max_nodes(limits.max_nodes);
  const uint64_t bound = search.Run(upper_bound);
  BranchAndBoundResult result;
  result.chosen = search.best();
  result.cells = search.best_cells();
  result.upper_bound = std::max(bound, result.cells);
  result.proven_optimal = result.upper_bound == result.cells;
  result.nodes = search.nodes();
  result.timed_out = search.timed_out();
  result.root_bound = std::max(std::min(search.root_bound(), upper_bound), result.cells);
  result.root_fixed_in = search.root_fixed_in();
  result.root_removed = search.root_removed();
  result.root_steps = search.root_steps();
  result.root_subgradient_bound = search.root_subgradient_bound();
  result.root_lp_bound = search.root_lp_bound();
  result.root_lp_seconds = search.root_lp_seconds();
  result.root_lp_optimal = search.root_lp_optimal();
  result.root_lp_improved = search.root_lp_improved();
  result.profile = search.profile();
  return result;
}

}  // namespace vantage::detail
