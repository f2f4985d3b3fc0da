#pragma once
/// Installation constraints on a constellation (issue 20, docs/constraints.md): pairs of
/// candidates that may not both be chosen (projector interference, minimum separation) and
/// calibration connectivity (the chosen sensors' overlap graph must be connected). Selection sees
/// only the matrix: the pipeline turns sensor types and poses into pairs, this header turns
/// observation sets into overlaps.
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "vantage/visibility.hpp"

namespace vantage {

/// Why two candidates may not both be chosen.
enum class ConflictKind {
  kInterference,  ///< both project light onto too much of each other's observed cells
  kSeparation,    ///< closer than the scene's min_separation
};

/// "interference", "separation" (report.json).
std::string ConflictKindName(ConflictKind kind);

/// Two candidates that may not both be chosen: a < b, candidate indices.
struct Conflict {
  uint32_t a = 0;
  uint32_t b = 0;
  ConflictKind kind = ConflictKind::kInterference;
  /// Interference: the shared share |O_a ∩ O_b| / min(|O_a|, |O_b|); separation: the distance [m].
  double value = 0;
};

/// Calibration connectivity: an edge joins two candidates that both see at least `min_cells`
/// cells of R, or (with `min_fraction`) at least that share of the smaller of their two sets
/// (and at least one cell). Exactly one of the two is set.
struct CalibrationRule {
  std::optional<uint64_t> min_cells;  ///< --calibration-overlap, cells >= 1
  std::optional<double> min_fraction;  ///< --calibration-overlap-frac, in (0, 1]
  /// Whether two sets of sizes `size_a`, `size_b` sharing `common` cells are joined.
  bool Joins(uint64_t common, uint64_t size_a, uint64_t size_b) const;
  /// Throws FieldError naming calibration_overlap / calibration_overlap_frac.
  void Validate() const;
};

/// The constraints a selection must satisfy. Empty: plain selection, exactly as without it.
struct InstallConstraints {
  /// Pairs that may not both be chosen, sorted by (a, b), a < b, unique per (a, b) (the first
  /// kind given wins).
  std::vector<Conflict> conflicts;
  /// Set: the chosen sensors must form a connected overlap graph.
  std::optional<CalibrationRule> calibration;
  bool empty() const { return conflicts.empty() && !calibration; }
  /// Throws FieldError naming `conflicts` (index out of range, a >= b, unsorted) or the
  /// calibration rule's field.
  void Validate(size_t candidate_count) const;
};

/// The cells of R a candidate's pixels reach, whatever the quality filter: what its projector
/// lights up (plain_reference_indices, or reference_indices without a filter).
std::span<const uint32_t> IlluminatedCells(const Observation& observation);

/// Interference pairs among `projecting` candidates (by index): a pair conflicts when the cells
/// both illuminate exceed `max_overlap` times the smaller of the two illuminated sets, i.e. when
/// either lights up more than that share of what the other observes. Sorted by (a, b). Stops
/// once it holds more than `max_pairs` (then max_pairs + 1 of them): a caller refuses that many.
std::vector<Conflict> InterferenceConflicts(
    std::span<const Observation> observations, const std::vector<bool>& projecting,
    double max_overlap, size_t max_pairs = std::numeric_limits<size_t>::max());

/// Adds `extra` to `conflicts`, keeping them sorted and unique per pair (existing kinds win).
void MergeConflicts(std::vector<Conflict> extra, std::vector<Conflict>* conflicts);

/// An edge of the overlap graph: candidates a < b and the cells of R both see (selection's
/// cells: reference_indices).
struct OverlapEdge {
  uint32_t a = 0;
  uint32_t b = 0;
  uint64_t cells = 0;
};

/// The edges among `among` (candidate indices) that `rule` joins, sorted by (a, b); every pair
/// with `rule` unset (rule.Joins is then "any common cell").
std::vector<OverlapEdge> OverlapGraph(std::span<const Observation> observations,
                                      std::span<const uint32_t> among,
                                      const std::optional<CalibrationRule>& rule);

/// What a constellation breaks.
struct ConstraintCheck {
  std::vector<Conflict> conflicts;  ///< conflicting pairs both chosen
  /// The chosen sensors' overlap graph under the calibration rule (all pairs with a common cell
  /// when there is none): its edges and connected components (each sorted, by first member).
  std::vector<OverlapEdge> edges;
  std::vector<std::vector<uint32_t>> components;
  bool connected() const { return components.size() <= 1; }
};

/// Checks `chosen` against `constraints` (conflicts listed there; connectivity by the rule).
ConstraintCheck CheckConstraints(std::span<const Observation> observations,
                                 std::span<const uint32_t> chosen,
                                 const InstallConstraints& constraints);

/// Kept sensors (`kept`, conflict-free) that the calibration rule leaves in parts, joined: `kept`
/// first, then the candidates of the shortest chains over the overlap graph that join the parts
/// (fewest sensors per chain; a heuristic), each conflicting with nothing chosen. `kept` itself
/// when it is connected or there is no rule; empty when no chain joins two parts. Selection
/// grows every answer from it (docs/constraints.md, Kept sensors).
std::vector<uint32_t> ConnectKept(std::span<const Observation> observations,
                                  std::span<const uint32_t> kept,
                                  const InstallConstraints& constraints);

/// The conflicts of `constraints` in which a chosen sensor excluded an unchosen candidate:
/// what the answer avoided, sorted by (a, b).
std::vector<Conflict> ConflictsAvoided(std::span<const uint32_t> chosen,
                                       const InstallConstraints& constraints);

}  // namespace vantage
