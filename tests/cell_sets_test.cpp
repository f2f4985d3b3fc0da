// Observe's per-hit work without divisions or sorts (issues 45, 47): each piece against the plain
// formula it replaces, written out here — the cell of a point by floor(p / F), the split of a
// candidate's hits by counting them in a std::map and merging with R, the aperture's field by
// the slopes y / x and z / x — on random input and on points placed exactly on the boundaries.
#include "observe/cell_sets.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <numbers>
#include <random>
#include <vector>

#include "observe/culling.hpp"
#include "vantage/sensors.hpp"
#include "vantage/types.hpp"

namespace vantage {
namespace {

using detail::CellIndex;
using detail::CellOfPoint;
using detail::CellSet;

// floor(x / F), as the specification states the cell (VoxelKeyOf's formula, written out).
int64_t DividedCell(double x, double cell) {
  const double q = x / cell;
  if (!(std::abs(q) < 0x1p62)) return q > 0 ? INT64_MAX : INT64_MIN;
  const double f = std::floor(q);
  return static_cast<int64_t>(f);
}

// Points on and beside the boundaries k F of a cell size: k F itself, its neighbours up to 4 ulps
// away, and points whose quotient is within a few ulps of an integer.
std::vector<double> BoundaryPoints(double cell, std::mt19937_64* rng) {
  std::vector<double> out;
  std::uniform_int_distribution<int64_t> k_of(-300000, 300000);
  for (int i = 0; i < 4000; ++i) {
    const int64_t k = i < 200 ? i - 100 : k_of(*rng);
    const double at = static_cast<double>(k) * cell;
    double up = at, down = at;
    out.push_back(at);
    for (int step = 0; step < 4; ++step) {
      up = std::nextafter(up, std::numeric_limits<double>::infinity());
      down = std::nextafter(down, -std::numeric_limits<double>::infinity());
      out.push_back(up);
      out.push_back(down);
    }
    // x whose quotient x / F rounds to the integer k or lands an ulp beside it.
    double q = static_cast<double>(k);
    for (int step = 0; step < 3; ++step) {
      out.push_back(q * cell);
      q = std::nextafter(q, std::numeric_limits<double>::infinity());
    }
  }
  for (const double x : {0.0, -0.0, 1e-310, -1e-310, 5e-324, -5e-324, 1e-300, -1e-300})
    out.push_back(x);
  return out;
}

TEST(CellOfPoint, EqualsTheDivisionOnBoundaryPoints) {
  std::mt19937_64 rng(45);
  // Cell sizes of the scenes and awkward ones: not dyadic, dyadic, tiny, huge.
  for (const double cell : {0.005, 0.001, 0.002, 0.01, 0.003, 0.0025, 0.1, 1.0 / 3, 0.007, 1e-5,
                            0.125, 1.0, 3e-7, 7.3, 1e300, 1e-310}) {
    const CellOfPoint cell_of(cell);
    size_t checked = 0;
    for (const double x : BoundaryPoints(cell, &rng)) {
      ASSERT_EQ(cell_of.Axis(x), DividedCell(x, cell)) << "x = " << x << ", F = " << cell;
      ++checked;
    }
    // Random points of a cell's range (a few metres, as observe's hits).
    std::uniform_real_distribution<double> coordinate(-5.0, 5.0);
    for (int i = 0; i < 100000; ++i) {
      const Vec3 p(coordinate(rng), coordinate(rng), coordinate(rng));
      const VoxelIndex got = cell_of(p);
      for (int a = 0; a < 3; ++a) ASSERT_EQ(got[a], DividedCell(p[a], cell)) << p[a] << " " << cell;
    }
    EXPECT_GT(checked, 30000u);
  }
  // Non-finite coordinates saturate as the division's do (VoxelIndexFits then rejects them).
  const CellOfPoint cell_of(0.005);
  for (const double x :
       {std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
        std::numeric_limits<double>::quiet_NaN(), 1e300, -1e300})
    EXPECT_EQ(cell_of.Axis(x), FloorToInt(x / 0.005)) << x;
}

// Axis(x, guess) is the division's cell whatever the guess: the true cell, its neighbours (a
// boundary point's other side), cells far off, and the extremes of a fitting index.
TEST(CellOfPoint, GuessedAxisEqualsTheDivision) {
  std::mt19937_64 rng(46);
  for (const double cell : {0.005, 0.001, 0.003, 1.0 / 3, 0.007, 1e-5, 0.125, 7.3, 1e300, 1e-310}) {
    const CellOfPoint cell_of(cell);
    std::uniform_int_distribution<int64_t> far(-kVoxelAxisOffset, kVoxelAxisOffset - 1);
    size_t checked = 0;
    for (const double x : BoundaryPoints(cell, &rng)) {
      const int64_t truth = DividedCell(x, cell);
      for (const int64_t guess : {truth, truth - 1, truth + 1, truth - 2, truth + 2, far(rng),
                                  int64_t{0}, -kVoxelAxisOffset, kVoxelAxisOffset - 1}) {
        if (std::abs(guess) > kVoxelAxisOffset) continue;  // fitting indices only
        ASSERT_EQ(cell_of.Axis(x, guess), truth) << "x = " << x << ", F = " << cell << ", guess " << guess;
        ++checked;
      }
    }
    EXPECT_GT(checked, 100000u);
    // A walk along a row of hits, each guessing the last one's cell (as observe does), with
    // the guess also given as doubles kept from the last cell (observe's Near).
    std::uniform_real_distribution<double> step(0.0, 2.5 * std::min(cell, 1.0));
    VoxelIndex last{0, 0, 0};
    std::array<double, 3> last_below{0, 0, 0};
    Vec3 p(-2.0, 0.5, -0.25);
    for (int i = 0; i < 20000; ++i) {
      p += Vec3(step(rng), -0.5 * step(rng), 0.25 * step(rng));
      const VoxelIndex got = cell_of.Near(p, last);
      for (int a = 0; a < 3; ++a) ASSERT_EQ(got[a], DividedCell(p[a], cell)) << p[a] << " " << cell;
      ASSERT_EQ(cell_of.Near(p, last, last_below), got);
      if (VoxelIndexFits(got)) {
        last = got;
        for (int a = 0; a < 3; ++a) last_below[a] = static_cast<double>(got[a]);
      }
    }
  }
}

TEST(CellOfPoint, PackingEqualsPackVoxel) {
  std::mt19937_64 rng(47);
  std::uniform_int_distribution<int64_t> axis(-kVoxelAxisOffset, kVoxelAxisOffset - 1);
  for (int i = 0; i < 10000; ++i) {
    const VoxelIndex index{axis(rng), axis(rng), axis(rng)};
    ASSERT_EQ(detail::PackFittingVoxel(index), PackVoxel(index));
  }
}

// R: `size` distinct random keys, sorted as Reference::keys is.
std::vector<uint64_t> RandomReference(size_t size, std::mt19937_64* rng) {
  std::uniform_int_distribution<int64_t> axis(-60, 60);
  std::vector<uint64_t> keys;
  while (keys.size() < size) {
    keys.push_back(PackVoxel({axis(*rng), axis(*rng), axis(*rng)}));
    if (keys.size() == size) {
      std::sort(keys.begin(), keys.end());
      keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
    }
  }
  return keys;
}

TEST(CellIndex, FindsEveryKeyOfRAndNoOther) {
  std::mt19937_64 rng(1);
  for (const size_t size : {size_t{0}, size_t{1}, size_t{7}, size_t{1000}, size_t{50000}}) {
    const std::vector<uint64_t> keys = RandomReference(size, &rng);
    const CellIndex index(keys);
    for (size_t i = 0; i < keys.size(); ++i)
      ASSERT_EQ(index.Find(keys[i]), static_cast<int64_t>(i));
    std::uniform_int_distribution<int64_t> axis(-80, 80);
    for (int i = 0; i < 20000; ++i) {
      const uint64_t key = PackVoxel({axis(rng), axis(rng), axis(rng)});
      const auto at = std::lower_bound(keys.begin(), keys.end(), key);
      const int64_t expected = at != keys.end() && *at == key ? at - keys.begin() : -1;
      ASSERT_EQ(index.Find(key), expected);
    }
  }
}

TEST(CellSets, SplitEqualsCountingTheHitsInAMap) {
  std::mt19937_64 rng(43);
  CellSet set;  // one set for every round: the marks must come back clear each time
  for (int round = 0; round < 300; ++round) {
    const size_t r_size = round % 5 == 0 ? rng() % 5 : 1 + rng() % 20000;
    const std::vector<uint64_t> keys = RandomReference(r_size, &rng);
    const CellIndex index(keys);
    const bool count = round % 3 != 2;
    const bool want_hits = round % 4 != 3;
    const bool want_outside = round % 5 != 4;
    set.Reset(index, count);
    // Hits: runs of repeated cells (neighbouring pixels), cells of R and others, some of them
    // met thousands of times (past kMaxPointCount).
    std::map<uint64_t, uint64_t> truth;  // key -> pixels
    const size_t hits = rng() % 60000;
    std::uniform_int_distribution<int64_t> axis(-70, 70);
    uint64_t key = PackVoxel({0, 0, 0});
    const bool hot = round % 7 == 0;
    for (size_t h = 0; h < hits; ++h) {
      if (rng() % 4 == 0) {
        if (!keys.empty() && rng() % 3 != 0)
          key = keys[rng() % keys.size()];
        else
          key = PackVoxel({axis(rng), axis(rng), axis(rng)});
        if (hot && !keys.empty()) key = keys[rng() % std::min<size_t>(keys.size(), 3)];
      }
      set.Add(key);
      ++truth[key];
    }
    std::vector<uint32_t> indices, expected_indices;
    std::vector<uint16_t> point_counts, expected_counts;
    std::vector<uint64_t> outside, expected_outside;
    for (const auto& [k, pixels] : truth) {  // the map walks the keys ascending, as R's indices
      const auto at = std::lower_bound(keys.begin(), keys.end(), k);
      if (at != keys.end() && *at == k) {
        expected_indices.push_back(static_cast<uint32_t>(at - keys.begin()));
        expected_counts.push_back(
            static_cast<uint16_t>(std::min<uint64_t>(pixels, kMaxPointCount)));
      } else {
        expected_outside.push_back(k);
      }
    }
    set.Take(&indices, want_hits ? &point_counts : nullptr, want_outside ? &outside : nullptr);
    ASSERT_EQ(indices, expected_indices) << "round " << round;
    if (count && want_hits)
      ASSERT_EQ(point_counts, expected_counts) << "round " << round;
    else
      ASSERT_TRUE(point_counts.empty());
    if (want_outside)
      ASSERT_EQ(outside, expected_outside) << "round " << round;
    else
      ASSERT_TRUE(outside.empty());
  }
}

// ApertureField::Contains as the division formula states it: the point in the aperture's frame,
// then its slopes right = -y/x, down = -z/x against the cone, the frustum or the image.
bool ContainsByDivision(const SensorType& camera,
                        const SecondAperture& aperture,
                        const Vec3& p_body) {
  const Mat3 aperture_from_body = BodyFromAperture(aperture).transpose();
  const Vec3 p = aperture_from_body * (p_body - ApertureCentreInBody(aperture));
  if (!(p.x() > 0)) return false;
  const double right = -p.y() / p.x(), down = -p.z() / p.x();
  if (aperture.cone > 0) return std::atan(std::hypot(right, down)) <= aperture.cone / 2;
  if (aperture.hfov > 0) {
    const double h = std::tan(aperture.hfov / 2);
    const double v = std::tan((aperture.vfov > 0 ? aperture.vfov : aperture.hfov) / 2);
    return std::abs(right) <= h && std::abs(down) <= v;
  }
  const bool own = aperture.width > 0;
  const double fx = own ? aperture.fx : camera.fx, fy = own ? aperture.fy : camera.fy;
  const double cx = own ? aperture.cx : camera.cx, cy = own ? aperture.cy : camera.cy;
  const int width = own ? aperture.width : camera.width,
            height = own ? aperture.height : camera.height;
  const double u = cx + fx * right, v = cy + fy * down;
  return u >= 0 && v >= 0 && u < width && v < height;
}

TEST(ApertureField, ContainsEqualsTheDivisions) {
  const SensorType camera = SensorType::FromFov("cam", 640, 480, 1.0, std::nullopt, 0.1, 4.0);
  std::vector<SecondAperture> apertures;
  for (const double toe_in : {0.0, 0.07, 0.3}) {
    for (const double baseline : {0.0, 0.075, 0.25}) {
      SecondAperture a;
      a.kind = SecondAperture::Kind::kProjector;
      a.baseline = baseline;
      a.toe_in = toe_in;
      apertures.push_back(a);  // the camera's own image
      a.hfov = 1.2;
      a.vfov = 0.9;
      apertures.push_back(a);  // a frustum
      a.vfov = 0;
      apertures.push_back(a);  // a square frustum
      a.hfov = a.vfov = 0;
      for (const double cone : {0.5, 1.4, 2.9, 3.1}) {
        a.cone = cone;
        apertures.push_back(a);  // cones, the widest beyond the quick test's range
      }
      a.cone = 0;
      a.kind = SecondAperture::Kind::kImager;
      a.width = 1280;
      a.height = 800;
      a.fx = a.fy = 900;
      a.cx = 641.5;
      a.cy = 399.25;
      apertures.push_back(a);  // its own intrinsics
      a.width = 0;
    }
  }
  std::mt19937_64 rng(47);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::uniform_real_distribution<double> depth(0.05, 4.0);
  size_t inside = 0, outside = 0;
  for (const SecondAperture& aperture : apertures) {
    const ApertureField field(camera, aperture);
    const Mat3 body_from_aperture = BodyFromAperture(aperture);
    const Vec3 centre = ApertureCentreInBody(aperture);
    // The field's edge in the aperture's frame at depth x: the slopes where the verdict turns.
    std::vector<std::pair<double, double>> edges;  // (right, down) on the edge
    if (aperture.cone > 0) {
      const double t = std::tan(aperture.cone / 2);
      for (int i = 0; i < 16; ++i)
        edges.emplace_back(t * std::cos(i * 0.39), t * std::sin(i * 0.39));
    } else if (aperture.hfov > 0) {
      const double h = std::tan(aperture.hfov / 2);
      const double v = std::tan((aperture.vfov > 0 ? aperture.vfov : aperture.hfov) / 2);
      for (const double f : {-1.0, -0.5, 0.0, 0.5, 1.0}) {
        edges.emplace_back(h, f * v);
        edges.emplace_back(-h, f * v);
        edges.emplace_back(f * h, v);
        edges.emplace_back(f * h, -v);
      }
    } else {
      const bool own = aperture.width > 0;
      const double fx = own ? aperture.fx : camera.fx, fy = own ? aperture.fy : camera.fy;
      const double cx = own ? aperture.cx : camera.cx, cy = own ? aperture.cy : camera.cy;
      const double w = own ? aperture.width : camera.width,
                   ht = own ? aperture.height : camera.height;
      // u = cx + fx right = 0 or w; v likewise.
      for (const double f : {0.0, 0.3, 1.0}) {
        edges.emplace_back((0 - cx) / fx, (f * ht - cy) / fy);
        edges.emplace_back((w - cx) / fx, (f * ht - cy) / fy);
        edges.emplace_back((f * w - cx) / fx, (0 - cy) / fy);
        edges.emplace_back((f * w - cx) / fx, (ht - cy) / fy);
      }
    }
    const auto check = [&](const Vec3& p_body) {
      const bool expected = ContainsByDivision(camera, aperture, p_body);
      ASSERT_EQ(field.Contains(p_body), expected)
          << "p_body = " << p_body.transpose() << ", cone " << aperture.cone << ", hfov "
          << aperture.hfov << ", width " << aperture.width << ", toe-in " << aperture.toe_in;
      ASSERT_EQ(InApertureField(camera, aperture, p_body), expected);
      (expected ? inside : outside) += 1;
    };
    for (int i = 0; i < 20000; ++i) {
      // Random points around the field, mostly in front.
      check(Vec3(depth(rng) * (i % 10 == 0 ? -1 : 1), 3 * unit(rng), 3 * unit(rng)));
    }
    for (const auto& [right, down] : edges) {
      for (int i = 0; i < 40; ++i) {
        const double x = i < 4 ? std::ldexp(1.0, i - 2) : depth(rng);
        // On the edge, a few ulps beside it, and about the quick test's margin (2^-30) away.
        for (const double scale : {1.0, 1.0 + 0x1p-52, 1.0 - 0x1p-53, 1.0 + 0x1p-40, 1.0 - 0x1p-40,
                                   1.0 + 0x1p-31, 1.0 - 0x1p-31, 1.0 + 0x1p-29, 1.0 - 0x1p-29,
                                   1.0 + 0x1p-27, 1.0 - 0x1p-27, 1.0 + 1e-6, 1.0 - 1e-6}) {
          const Vec3 p_aperture(x, -right * scale * x, -down * scale * x);
          check(body_from_aperture * p_aperture + centre);
          // Without toe-in the body point is exact: its aperture frame point lies on the edge.
          if (aperture.toe_in == 0) check(p_aperture + centre);
        }
      }
    }
    // Points off the doubles' finite range: as the division formula (the rotation's 0 · inf).
    constexpr double kInf = std::numeric_limits<double>::infinity();
    const double nan = std::numeric_limits<double>::quiet_NaN();
    for (const Vec3& p : {Vec3(kInf, 0.1, 0.1), Vec3(kInf, 0, 0), Vec3(1, kInf, 0), Vec3(1, 0, -kInf),
                          Vec3(-kInf, 0, 0), Vec3(nan, 0, 0), Vec3(1, nan, 0), Vec3(1e308, -1e308, 0)})
      check(p);
  }
  EXPECT_GT(inside, 100000u);
  EXPECT_GT(outside, 100000u);
}

// Culling's spans (a bitmap of the projected rectangles): in row order, each row's spans apart
// (not even touching), inside the image, and covering every pixel whose centre ray meets a block
// within [near, far] (a slab test written here).
TEST(Culling, SpansAreOrderedApartAndCoverEveryRayThatMeetsABlock) {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (int round = 0; round < 12; ++round) {
    Candidate c;
    c.sensor =
        SensorType::FromFov("cam", 150 + 7 * round, 100 + 3 * round, 1.0, std::nullopt, 0.2, 3.0);
    // Looking along -z from 1.5 m above, tilted a little each round.
    const Quat down(Eigen::AngleAxisd(0.05 * round, Vec3::UnitX()) *
                    Eigen::AngleAxisd(std::numbers::pi / 2, Vec3::UnitY()));
    c.world_from_body = Pose{Vec3(0.1 * unit(rng), 0.1 * unit(rng), 1.5), down};
    std::vector<Aabb> blocks;
    for (int b = 0; b < 40; ++b) {
      Aabb box;
      const Vec3 lo(0.6 * unit(rng), 0.6 * unit(rng), 0.3 * unit(rng));
      box.Extend(lo);
      box.Extend(lo +
                 Vec3(0.02 + 0.1 * std::abs(unit(rng)), 0.02, 0.02 + 0.05 * std::abs(unit(rng))));
      blocks.push_back(box);
    }
    const std::vector<detail::RowSpan> spans = detail::SpansToTrace(c, blocks, true);
    std::vector<std::vector<uint8_t>> in(
        static_cast<size_t>(c.sensor.height),
        std::vector<uint8_t>(static_cast<size_t>(c.sensor.width), 0));
    for (size_t i = 0; i < spans.size(); ++i) {
      const detail::RowSpan& s = spans[i];
      ASSERT_TRUE(s.v >= 0 && s.v < c.sensor.height && s.u0 >= 0 && s.u0 <= s.u1 &&
                  s.u1 < c.sensor.width);
      if (i > 0) {
        const detail::RowSpan& p = spans[i - 1];
        ASSERT_TRUE(p.v < s.v || (p.v == s.v && p.u1 + 1 < s.u0))
            << "spans out of order or touching";
      }
      for (int u = s.u0; u <= s.u1; ++u) in[static_cast<size_t>(s.v)][static_cast<size_t>(u)] = 1;
    }
    const Mat3 rotation = c.world_from_body.rotation.toRotationMatrix();
    size_t meeting = 0;
    for (int v = 0; v < c.sensor.height; ++v) {
      for (int u = 0; u < c.sensor.width; ++u) {
        const Vec3 d = rotation * PixelRayInBody(c.sensor, u, v);  // depth t along it
        for (const Aabb& box : blocks) {
          double t0 = c.sensor.near, t1 = c.sensor.far;
          for (int a = 0; a < 3 && t0 <= t1; ++a) {
            const double o = c.world_from_body.position[a];
            if (d[a] == 0) {
              if (o < box.min[a] || o > box.max[a]) t0 = t1 + 1;
              continue;
            }
            double ta = (box.min[a] - o) / d[a], tb = (box.max[a] - o) / d[a];
            if (ta > tb) std::swap(ta, tb);
            t0 = std::max(t0, ta);
            t1 = std::min(t1, tb);
          }
          if (t0 <= t1) {
            ++meeting;
            ASSERT_TRUE(in[static_cast<size_t>(v)][static_cast<size_t>(u)])
                << "pixel " << u << ", " << v;
            break;
          }
        }
      }
    }
    EXPECT_GT(meeting, 100u) << "round " << round;
  }
}

// CornersInBody shares products among the corners; each corner equals Pose::operator* bit for
// bit (the spans then equal the per-corner rule's, tested above, in every rounding case).
TEST(Culling, CornersInBodyEqualThePoseProductBitForBit) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (int round = 0; round < 20000; ++round) {
    const Vec3 axis = Vec3(unit(rng), unit(rng), unit(rng)).normalized();
    const double scale = std::pow(10.0, 3 * unit(rng));
    const Pose pose{Vec3(scale * unit(rng), scale * unit(rng), scale * unit(rng)),
                    Quat(Eigen::AngleAxisd(std::numbers::pi * unit(rng), axis))};
    Aabb box;
    const Vec3 lo(scale * unit(rng), scale * unit(rng), scale * unit(rng));
    box.Extend(lo);
    box.Extend(lo + scale * Vec3(std::abs(unit(rng)), std::abs(unit(rng)), std::abs(unit(rng))));
    const detail::BodyCorners corners = detail::CornersInBody(pose, box);
    for (int k = 0; k < 8; ++k) {
      const Vec3 corner((k & 1) ? box.max.x() : box.min.x(), (k & 2) ? box.max.y() : box.min.y(),
                        (k & 4) ? box.max.z() : box.min.z());
      const Vec3 body = pose * corner;
      ASSERT_EQ(corners.x[k], body.x()) << "round " << round << " corner " << k;
      ASSERT_EQ(corners.y[k], body.y()) << "round " << round << " corner " << k;
      ASSERT_EQ(corners.z[k], body.z()) << "round " << round << " corner " << k;
    }
  }
}

// Culling's spans equal the rule computed the plain way, corner by corner: each block's corners
// through Pose::operator* and ProjectBodyPoint, the bounding rectangle of the projections padded
// by one pixel (the whole image where a corner lies on or behind the camera plane, none beyond
// [near, far]), their union as a pixel mask, its maximal runs per row. Random cameras (any
// orientation) and boxes, near, behind and across the camera.
TEST(Culling, SpansEqualThePerCornerProjection) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  size_t traced = 0;
  for (int round = 0; round < 200; ++round) {
    Candidate c;
    c.sensor = SensorType::FromFov("cam", 64 + round % 97, 48 + round % 61, 0.6 + 0.01 * (round % 90),
                                   std::nullopt, 0.05 + 0.002 * (round % 50), 1.0 + 0.02 * round);
    const Vec3 axis = Vec3(unit(rng), unit(rng), unit(rng)).normalized();
    c.world_from_body = Pose{Vec3(0.5 * unit(rng), 0.5 * unit(rng), 0.5 * unit(rng)),
                             Quat(Eigen::AngleAxisd(std::numbers::pi * unit(rng), axis))};
    std::vector<Aabb> blocks;
    for (int b = 0; b < 30; ++b) {
      Aabb box;
      const Vec3 lo(2 * unit(rng), 2 * unit(rng), 2 * unit(rng));
      box.Extend(lo);
      box.Extend(lo + Vec3(0.3 * std::abs(unit(rng)), 0.3 * std::abs(unit(rng)), 0.3 * std::abs(unit(rng))));
      blocks.push_back(box);
    }
    const SensorType& s = c.sensor;
    const Pose body_from_world = c.world_from_body.Inverse();
    std::vector<std::vector<uint8_t>> mask(static_cast<size_t>(s.height),
                                           std::vector<uint8_t>(static_cast<size_t>(s.width), 0));
    for (const Aabb& box : blocks) {
      double depth_min = std::numeric_limits<double>::infinity(), depth_max = -depth_min;
      double u_min = depth_min, u_max = -depth_min, v_min = depth_min, v_max = -depth_min;
      for (int k = 0; k < 8; ++k) {
        const Vec3 corner((k & 1) ? box.max.x() : box.min.x(), (k & 2) ? box.max.y() : box.min.y(),
                          (k & 4) ? box.max.z() : box.min.z());
        const Vec3 body = body_from_world * corner;
        depth_min = std::min(depth_min, body.x());
        depth_max = std::max(depth_max, body.x());
        if (const auto uv = ProjectBodyPoint(s, body)) {
          u_min = std::min(u_min, uv->x());
          u_max = std::max(u_max, uv->x());
          v_min = std::min(v_min, uv->y());
          v_max = std::max(v_max, uv->y());
        }
      }
      const double slack = 1e-6 * (1.0 + s.far);
      if (depth_max < s.near - slack || depth_min > s.far + slack) continue;
      int u0 = 0, v0 = 0, u1 = s.width - 1, v1 = s.height - 1;
      if (depth_min > 1e-9) {
        const auto clamp = [](double x) { return static_cast<int>(std::min(1e9, std::max(-1.0, x))); };
        u0 = std::max(0, clamp(std::ceil(u_min - 0.5) - 1));
        v0 = std::max(0, clamp(std::ceil(v_min - 0.5) - 1));
        u1 = std::min(s.width - 1, clamp(std::floor(u_max - 0.5) + 1));
        v1 = std::min(s.height - 1, clamp(std::floor(v_max - 0.5) + 1));
      }
      for (int v = v0; v <= v1; ++v)
        for (int u = u0; u <= u1; ++u) mask[static_cast<size_t>(v)][static_cast<size_t>(u)] = 1;
    }
    std::vector<detail::RowSpan> expected;
    for (int v = 0; v < s.height; ++v) {
      for (int u = 0; u < s.width; ++u) {
        if (!mask[static_cast<size_t>(v)][static_cast<size_t>(u)]) continue;
        if (!expected.empty() && expected.back().v == v && expected.back().u1 == u - 1) {
          ++expected.back().u1;
        } else {
          expected.push_back({v, u, u});
        }
        ++traced;
      }
    }
    const std::vector<detail::RowSpan> spans = detail::SpansToTrace(c, blocks, true);
    ASSERT_EQ(spans.size(), expected.size()) << "round " << round;
    for (size_t i = 0; i < spans.size(); ++i) {
      ASSERT_EQ(spans[i].v, expected[i].v) << "round " << round << " span " << i;
      ASSERT_EQ(spans[i].u0, expected[i].u0) << "round " << round << " span " << i;
      ASSERT_EQ(spans[i].u1, expected[i].u1) << "round " << round << " span " << i;
    }
  }
  EXPECT_GT(traced, 100000u);
}

}  // namespace
}  // namespace vantage
