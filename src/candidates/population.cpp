// Clone positions of a Gazebo <population> (GAZEBO.md, "Sensor populations"), reproducing
// gazebo/physics/Population.cc: the same regions, distributions, offsets and quirks; only the
// random numbers differ (vantage's keyed streams instead of Gazebo's global generator).
#include <fmt/format.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "candidates/kmeans.hpp"
#include "vantage/candidates.hpp"
#include "vantage/error.hpp"
#include "vantage/rng.hpp"

namespace vantage {
namespace {

/// Bounds that keep a typo (model_count 1e9, a 10 km box) from exhausting memory.
constexpr int64_t kMaxClones = 1'000'000;
constexpr double kMaxLatticePoints = 1'000'000;
/// Gazebo's lattice step of the box `uniform` distribution [m].
constexpr double kLatticeStep = 0.1;
/// Gazebo's sample count of the cylinder `uniform` distribution.
constexpr int kCylinderSamples = 10'000;

const char* RegionName(RegionShape region) {
  switch (region) {
    case RegionShape::kBox:
      return "box";
    case RegionShape::kCylinder:
      return "cylinder";
    case RegionShape::kNone:
      return "no region";
  }
  return "?";
}

const char* DistributionName(Distribution distribution) {
  switch (distribution) {
    case Distribution::kRandom:
      return "random";
    case Distribution::kUniform:
      return "uniform";
    case Distribution::kGrid:
      return "grid";
    case Distribution::kLinearX:
      return "linear-x";
    case Distribution::kLinearY:
      return "linear-y";
    case Distribution::kLinearZ:
      return "linear-z";
  }
  return "?";
}

[[noreturn]] void Fail(const Population& p, const std::string& message) {
  throw InputError(AtPlace(p.file, p.line, fmt::format("population '{}': {}", p.name, message)));
}

bool IsFinite(const Vec3& v) { return v.allFinite(); }

std::string Str(const Vec3& v) { return fmt::format("{} {} {}", v.x(), v.y(), v.z()); }

/// Checks everything Gazebo's ParseSdf checks, plus what would make vantage misbehave (NaN,
/// sizes that exhaust memory); Gazebo ignores such a population with a warning, vantage stops.
void Validate(const Population& p) {
  if (!IsFinite(p.pose.position) || !p.pose.rotation.coeffs().allFinite())
    Fail(p, "<pose> is not finite — give six numbers x y z roll pitch yaw");
  const bool is_grid = p.distribution == Distribution::kGrid;
  const bool is_linear = p.distribution == Distribution::kLinearX ||
                         p.distribution == Distribution::kLinearY ||
                         p.distribution == Distribution::kLinearZ;
  // Supported combinations: Population.cc's PopulateOne. Gazebo never reads a region for grid;
  // vantage accepts a box there (ignored, as in Gazebo) but rejects a cylinder as a mistake.
  const bool is_supported = is_grid ? p.region != RegionShape::kCylinder
                                    : (p.region == RegionShape::kBox ||
                                       (p.region == RegionShape::kCylinder && !is_linear));
  if (!is_supported) {
    Fail(p, fmt::format("distribution '{}' with {} is not supported — use box or cylinder with "
                        "random/uniform, box with linear-x/-y/-z, or grid without a region",
                        DistributionName(p.distribution), RegionName(p.region)));
  }
  if (is_grid) {
    if (p.rows < 1 || p.cols < 1)
      Fail(p,
           fmt::format("grid of {} rows x {} cols — give <rows> and <cols> >= 1", p.rows, p.cols));
    if (int64_t{p.rows} * p.cols > kMaxClones)
      Fail(p, fmt::format("grid of {} x {} sensors is above {} — use fewer rows or cols", p.rows,
                          p.cols, kMaxClones));
    if (!IsFinite(p.step)) Fail(p, "grid <step> is not finite — give three numbers dx dy dz");
    return;
  }
  if (p.count < 1) Fail(p, fmt::format("<model_count> is {} — give at least 1", p.count));
  if (p.count > kMaxClones)
    Fail(p, fmt::format("<model_count> {} is above {} — use fewer clones", p.count, kMaxClones));
  if (p.region == RegionShape::kBox) {
    if (!IsFinite(p.box_size) || (p.box_size.array() <= 0).any())
      Fail(p, fmt::format("box <size> ({}) must be three positive lengths [m]", Str(p.box_size)));
  } else {
    if (!std::isfinite(p.radius) || p.radius <= 0)
      Fail(p, fmt::format("cylinder <radius> {} must be positive [m]", p.radius));
    if (!std::isfinite(p.length) || p.length <= 0)
      Fail(p, fmt::format("cylinder <length> {} must be positive [m]", p.length));
  }
}

/// Gazebo's `(offset + pose).pos`: the offset expressed in the (shifted) population frame.
Vec3 Place(const Vec3& origin, const Quat& rotation, const Vec3& offset) {
  return origin + rotation * offset;
}

/// A point of the cylinder region in its own frame, drawn as Gazebo does: ang, then ρ uniform in
/// radius (not in area, so points crowd the axis), then z.
Vec3 CylinderPoint(Rng* rng, double radius, double length) {
  const double angle = rng->Uniform(0.0, 2.0 * std::numbers::pi);
  const double rho = rng->Uniform(0.0, radius);
  const double z = rng->Uniform(0.0, length);
  return Vec3(rho * std::cos(angle), rho * std::sin(angle), z);
}

/// Box `uniform`: Gazebo's lattice, built with the same accumulated `+= .1` so that the number of
/// points per row matches Gazebo's floating-point loop exactly.
std::vector<Vec3> BoxLattice(const Population& p, uint64_t seed, uint32_t population_index) {
  const Vec3& size = p.box_size;
  const double estimate =
      (std::floor(size.x() / kLatticeStep) + 1) * (std::floor(size.y() / kLatticeStep) + 1);
  if (estimate > kMaxLatticePoints)
    Fail(p, fmt::format("uniform box of {} x {} m has about {} lattice points (> {}) — use a "
                        "smaller box or the random distribution",
                        size.x(), size.y(), estimate, kMaxLatticePoints));
  std::vector<Vec3> lattice;
  double y = 0.0;
  while (y < size.y()) {
    double x = 0.0;
    while (x < size.x()) {
      Rng rng(seed, Stream::kPopulation, population_index, lattice.size());
      lattice.emplace_back(x, y, rng.Uniform(0.0, size.z()));
      x += kLatticeStep;
    }
    y += kLatticeStep;
  }
  if (lattice.size() < static_cast<size_t>(p.count)) {
    // Gazebo's Kmeans::Cluster refuses k > points and Population.cc then reads past the empty
    // centroid vector (undefined behaviour); here it is the user's error.
    Fail(p, fmt::format("uniform box of {} x {} m holds only {} points of Gazebo's 0.1 m lattice, "
                        "fewer than <model_count> {} — enlarge the box or lower model_count",
                        size.x(), size.y(), lattice.size(), p.count));
  }
  return lattice;
}

}  // namespace

std::vector<Vec3> PopulationPositions(const Population& population,
                                      uint64_t seed,
                                      uint32_t population_index) {
  const Population& p = population;
  Validate(p);
  const Quat& rotation = p.pose.rotation;
  std::vector<Vec3> positions;

  if (p.distribution == Distribution::kGrid) {
    // Population.cc centres the grid by shifting P's x and y in world axes, before rotation
    // (its even/odd branches both equal step·(n−1)/2); offsets are (j·dx, i·dy, 0).
    Vec3 origin = p.pose.position;
    origin.x() -= p.step.x() * (p.cols - 1) / 2.0;
    origin.y() -= p.step.y() * (p.rows - 1) / 2.0;
    positions.reserve(static_cast<size_t>(p.rows) * static_cast<size_t>(p.cols));
    for (int i = 0; i < p.rows; ++i) {
      for (int j = 0; j < p.cols; ++j) {
        positions.push_back(Place(origin, rotation, Vec3(j * p.step.x(), i * p.step.y(), 0.0)));
      }
    }
    return positions;
  }

  const auto count = static_cast<size_t>(p.count);
  positions.reserve(count);

  if (p.region == RegionShape::kCylinder) {
    // No shift for a cylinder: P is the centre of its base.
    const Vec3& origin = p.pose.position;
    if (p.distribution == Distribution::kRandom) {
      for (size_t i = 0; i < count; ++i) {
        Rng rng(seed, Stream::kPopulation, population_index, i);
        positions.push_back(Place(origin, rotation, CylinderPoint(&rng, p.radius, p.length)));
      }
      return positions;
    }
    // uniform: Gazebo's 10 000 random points, then k-means.
    if (p.count > kCylinderSamples)
      Fail(p, fmt::format("uniform cylinder clusters {} points: <model_count> {} is above that — "
                          "lower model_count",
                          kCylinderSamples, p.count));
    std::vector<Vec3> samples;
    samples.reserve(kCylinderSamples);
    for (int i = 0; i < kCylinderSamples; ++i) {
      Rng rng(seed, Stream::kPopulation, population_index, static_cast<uint64_t>(i));
      samples.push_back(CylinderPoint(&rng, p.radius, p.length));
    }
    for (const Vec3& centroid : detail::KMeans(samples, p.count))
      positions.push_back(Place(origin, rotation, centroid));
    return positions;
  }

  // Box: Population.cc's `pose.pos -= size / 2` happens in world axes before the offsets are
  // rotated, so a rotated box region is not centred on P (GAZEBO.md quirk, reproduced).
  const Vec3& size = p.box_size;
  const Vec3 origin = p.pose.position - size / 2.0;
  const auto n = static_cast<double>(p.count);
  switch (p.distribution) {
    case Distribution::kRandom:
      for (size_t i = 0; i < count; ++i) {
        Rng rng(seed, Stream::kPopulation, population_index, i);
        const double x = rng.Uniform(0.0, size.x());
        const double y = rng.Uniform(0.0, size.y());
        const double z = rng.Uniform(0.0, size.z());
        positions.push_back(Place(origin, rotation, Vec3(x, y, z)));
      }
      break;
    case Distribution::kUniform: {
      const std::vector<Vec3> lattice = BoxLattice(p, seed, population_index);
      for (const Vec3& centroid : detail::KMeans(lattice, p.count))
        positions.push_back(Place(origin, rotation, centroid));
      break;
    }
    // Linear: offsets size·i/n along the axis (the last clone stops one step short of the far
    // face), the other two coordinates at mid-size.
    case Distribution::kLinearX:
      for (size_t i = 0; i < count; ++i) {
        const Vec3 offset(size.x() * static_cast<double>(i) / n, size.y() / 2.0, size.z() / 2.0);
        positions.push_back(Place(origin, rotation, offset));
      }
      break;
    case Distribution::kLinearY:
      for (size_t i = 0; i < count; ++i) {
        const Vec3 offset(size.x() / 2.0, size.y() * static_cast<double>(i) / n, size.z() / 2.0);
        positions.push_back(Place(origin, rotation, offset));
      }
      break;
    case Distribution::kLinearZ:
      for (size_t i = 0; i < count; ++i) {
        const Vec3 offset(size.x() / 2.0, size.y() / 2.0, size.z() * static_cast<double>(i) / n);
        positions.push_back(Place(origin, rotation, offset));
      }
      break;
    case Distribution::kGrid:
      VANTAGE_CHECK(false);  // handled above
  }
  return positions;
}

}  // namespace vantage
