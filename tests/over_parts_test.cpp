// --over-parts (issue 42's demonstration objective): the most coverage of the worst (or the mean)
// target part, each part weighted alike. Checked against enumeration on small random matrices,
// and end to end on a scene of four parts.
#include <gtest/gtest.h>

#include <algorithm>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <vector>

#include "pipeline/common.hpp"
#include "test_util.hpp"
#include "vantage/error.hpp"
#include "vantage/pipeline.hpp"

namespace vantage {
namespace {

// A matrix of `candidates` rows over `cells` cells in `parts` parts (cell c in part c % parts),
// each candidate seeing each cell with probability 0.3.
VisibilityFile RandomMatrix(uint32_t seed, size_t candidates, size_t cells, size_t parts) {
  std::mt19937 rng(seed);
  std::bernoulli_distribution sees(0.3);
  VisibilityFile data;
  for (size_t c = 0; c < cells; ++c) {
    data.reference.keys.push_back(c);
    data.reference.part_of.push_back(static_cast<uint32_t>(c % parts));
  }
  for (size_t p = 0; p < parts; ++p) data.reference.part_names.push_back("part" + std::to_string(p));
  data.observations.resize(candidates);
  for (Observation& o : data.observations)
    for (uint32_t c = 0; c < cells; ++c)
      if (sees(rng)) o.reference_indices.push_back(c);
  return data;
}

// Each part's share of its cells seen by at least k of `chosen`, aggregated by min or mean.
double PartsValue(const VisibilityFile& data, const std::vector<uint32_t>& chosen, int k,
                  OverStates over) {
  const size_t parts = data.reference.part_names.size();
  std::vector<int> seers(data.reference.size(), 0);
  for (uint32_t i : chosen)
    for (uint32_t c : data.observations[i].reference_indices) ++seers[c];
  std::vector<double> seen(parts, 0), size(parts, 0);
  for (size_t c = 0; c < seers.size(); ++c) {
    size[data.reference.part_of[c]] += 1;
    if (seers[c] >= k) seen[data.reference.part_of[c]] += 1;
  }
  double min = 1, sum = 0;
  for (size_t p = 0; p < parts; ++p) {
    min = std::min(min, seen[p] / size[p]);
    sum += seen[p] / size[p];
  }
  return over == OverStates::kMin ? min : sum / static_cast<double>(parts);
}

// The best value over every set of n candidates.
double Enumerated(const VisibilityFile& data, int n, int k, OverStates over) {
  const size_t m = data.observations.size();
  std::vector<bool> pick(m, false);
  std::fill(pick.begin(), pick.begin() + n, true);
  double best = 0;
  do {
    std::vector<uint32_t> chosen;
    for (uint32_t i = 0; i < m; ++i)
      if (pick[i]) chosen.push_back(i);
    best = std::max(best, PartsValue(data, chosen, k, over));
  } while (std::prev_permutation(pick.begin(), pick.end()));
  return best;
}

TEST(OverParts, ExactIsTheEnumeratedOptimumAndTheOthersAreScoredAsTheyChose) {
  for (uint32_t seed = 1; seed <= 6; ++seed) {
    const VisibilityFile data = RandomMatrix(seed, 10, 36, seed % 3 + 2);
    for (const OverStates over : {OverStates::kMin, OverStates::kMean}) {
      for (const int k : {1, 2}) {
        for (int n = k; n <= 3; ++n) {
          SCOPED_TRACE(::testing::Message() << "seed " << seed << " n " << n << " k " << k
                                            << " over " << OverStatesName(over));
          SelectionRequest request;
          request.over_parts = over;
          const double optimum = Enumerated(data, n, k, over);
          for (const Method method : {Method::kExact, Method::kGreedy, Method::kLocal}) {
            SelectOptions options;
            options.n = n;
            options.k = k;
            options.method = method;
            options.time_limit = 20;
            Report report;
            detail::SelectOnMatrix(data, request, options, &report);
            ASSERT_FALSE(report.results.empty());
            const Selection& s = report.results.back();
            EXPECT_EQ(s.chosen.size(), static_cast<size_t>(n));
            EXPECT_NEAR(s.coverage, PartsValue(data, s.chosen, k, over), 1e-12);
            EXPECT_LE(s.coverage, optimum + 1e-12);
            if (method == Method::kExact) {
              EXPECT_NEAR(s.coverage, optimum, 1e-12);
              EXPECT_TRUE(s.proven_optimal);
            }
          }
        }
      }
    }
  }
}

// The calibration rule joins two sensors by the cells of R they both see, whatever part those lie
// in: it counted only the first part's cells (the first group's matrix). Parts {0, 1} and
// {2, 3}; A sees 0 and 2, B sees 2 and 3, C sees 1. With one common cell joining, only A and B
// are joined (cell 2, in part 1), so the one pair allowed is {A, B}: worst part 1/2.
TEST(OverParts, TheCalibrationRuleCountsCommonCellsOfEveryPart) {
  VisibilityFile data;
  data.reference.keys = {0, 1, 2, 3};
  data.reference.part_of = {0, 0, 1, 1};
  data.reference.part_names = {"left", "right"};
  data.observations.resize(3);
  data.observations[0].reference_indices = {0, 2};
  data.observations[1].reference_indices = {2, 3};
  data.observations[2].reference_indices = {1};
  SelectionRequest request;
  request.over_parts = OverStates::kMin;
  for (const Method method : {Method::kExact, Method::kGreedy, Method::kLocal}) {
    SCOPED_TRACE(MethodName(method));
    SelectOptions options;
    options.n = 2;
    options.method = method;
    options.time_limit = 20;
    options.constraints.calibration = CalibrationRule{.min_cells = 1};
    Report report;
    detail::SelectOnMatrix(data, request, options, &report);
    ASSERT_FALSE(report.results.empty());
    const Selection& s = report.results.back();
    std::vector<uint32_t> chosen = s.chosen;
    std::sort(chosen.begin(), chosen.end());
    EXPECT_EQ(chosen, (std::vector<uint32_t>{0, 1}));
    EXPECT_DOUBLE_EQ(s.coverage, 0.5);
  }
}

TEST(OverParts, AMatrixWithoutPartsIsRefused) {
  VisibilityFile data = RandomMatrix(1, 4, 8, 2);
  data.reference.part_of.clear();
  SelectionRequest request;
  request.over_parts = OverStates::kMin;
  Report report;
  try {
    detail::SelectOnMatrix(data, request, SelectOptions{}, &report);
    ADD_FAILURE() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--over-parts"), std::string::npos) << e.what();
  }
}

// End to end on a scene of four parts: the worst part's coverage is what exact maximised, and it
// is at least the worst part of the plain coverage's optimum.
TEST(OverParts, TheWorstPartIsRaised) {
  const test::TempDir dir;
  const std::string scene = std::string(VANTAGE_SOURCE_DIR) + "/examples/scenes/deep_bin.yaml";
  const auto worst_part = [](const nlohmann::json& result) {
    double worst = 1;
    for (const auto& [part, coverage] : result["part_coverage"].items())
      worst = std::min(worst, coverage.get<double>());
    return worst;
  };
  ASSERT_EQ(test::RunVantage("optimize " + scene + " -n 2 --method exact --out " +
                             dir.File("plain"))
                .exit_code,
            0);
  const test::CommandResult run = test::RunVantage(
      "optimize " + scene + " -n 2 --method exact --over-parts min --out " + dir.File("parts"));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("objective        the worst of the target parts' coverages"),
            std::string::npos)
      << run.out;
  const nlohmann::json plain = nlohmann::json::parse(test::ReadText(dir.File("plain/report.json")));
  const nlohmann::json parts = nlohmann::json::parse(test::ReadText(dir.File("parts/report.json")));
  const nlohmann::json& best = parts["results"].back();
  EXPECT_TRUE(best["optimal"].get<bool>());
  EXPECT_NEAR(best["coverage"].get<double>(), worst_part(best), 1e-12);
  EXPECT_GE(worst_part(best), worst_part(plain["results"].back()));
  EXPECT_EQ(parts["inputs"]["over_parts"], "min");
  // Refused where the parts' coverages are not what is counted.
  const test::CommandResult refused = test::RunVantage(
      "optimize " + scene + " -n 2 --method greedy --refine --over-parts min --out " +
      dir.File("refused"));
  EXPECT_EQ(refused.exit_code, 2);
  EXPECT_NE(refused.err.find("--over-parts: counts an aggregate of groups of cells, which --refine "
                             "does not"),
            std::string::npos)
      << refused.err;
}

}  // namespace
}  // namespace vantage
