#include "vantage/observe.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>

#include "observe/arm_occlusion.hpp"
#include "observe/cell_sets.hpp"
#include "observe/culling.hpp"
#include "vantage/ray_scene.hpp"
#include "vantage/error.hpp"
#include "vantage/interrupt.hpp"

namespace vantage {
namespace {

using detail::ReferenceBlocks;
using detail::RowSpan;
using detail::SpansToTrace;

// The physical model of one candidate (issue 43): where its second aperture is in the world, and
// what a hit must satisfy besides the ideal pinhole's.
struct PhysicalModel {
  const SecondAperture* aperture = nullptr;  // null: none
  std::optional<double> flying;              // time of flight's flying-pixel threshold [m]
  Vec3 centre;                               // the aperture's optical centre, world
  double nearest = 0;                        // stereo's nearest depth [m]
  bool active() const { return aperture != nullptr || flying.has_value(); }
};

PhysicalModel MakePhysicalModel(const Candidate& candidate, bool physical) {
  PhysicalModel model;
  if (!physical) return model;
  model.flying = FlyingPixelThresholdOf(candidate.sensor, candidate.type_id);
  model.aperture = SecondApertureOf(candidate.sensor, candidate.type_id);
  if (!model.aperture) return model;
  const Pose& pose = candidate.world_from_body;
  model.centre = pose.position + pose.rotation * ApertureCentreInBody(*model.aperture);
  model.nearest = StereoNearestDepth(candidate.sensor, *model.aperture);
  return model;
}

// Judges each pixel's first hit as the sensor model and the quality filter say and collects the
// cells: the ideal pinhole's, and under the physical model those the second aperture also sees,
// tested for occluders 16 segments at a time (one Embree packet).
class PixelJudge {
 public:
  // `placed`: the cell with the carrying arm as it stands in this view (none: the cell alone). The
  // second aperture's segments are tested against it too: a link between the projector or second
  // imager and a point hides the point as it hides the primary ray.
  // `sets`: the worker's cell sets (reset here), `index`: R's keys.
  PixelJudge(const RayScene& rays, const PlacedRayScene* placed, const Candidate& candidate,
             const Reference& reference, const detail::CellIndex& index,
             const ObserveOptions& options, detail::CellSets* sets, Observation* observation)
      : rays_(rays),
        placed_(placed),
        sensor_(candidate.sensor),
        world_from_body_(candidate.world_from_body.rotation.toRotationMatrix()),
        origin_(candidate.world_from_body.position),
        cell_of_(reference.cell_size),
        quality_(options.quality),
        min_cos_incidence_(quality_.max_incidence_deg
                               ? std::cos(*quality_.max_incidence_deg * std::numbers::pi / 180.0)
                               : -1.0),
        noise_(quality_.max_depth_noise ? NoiseModelOf(candidate) : nullptr),
        physical_(MakePhysicalModel(candidate, options.physical.value_or(true))),
        aperture_field_(physical_.aperture
                            ? std::optional<ApertureField>(std::in_place, sensor_, *physical_.aperture)
                            : std::nullopt),
        count_(options.count_points),
        observation_(observation),
        keys_(sets->all),
        quality_keys_(sets->quality),
        ideal_keys_(sets->ideal),
        index_(index) {
    keys_.Reset(index, count_ && !quality_.active());
    if (quality_.active()) quality_keys_.Reset(index, count_);
    if (physical_.active()) ideal_keys_.Reset(index, false);
    for (int a = 0; a < 3; ++a) segments_.origin[a] = static_cast<float>(physical_.centre[a]);
    // Stop 0.01 % short of the point: the surface it lies on must not occlude it, whatever float
    // rounding does to the segment's end.
    segments_.tfar = 1.0f - 1e-4f;
  }

  const PhysicalModel& physical() const { return physical_; }

  // A packet's first hits (no flying-pixel filter), in lane order. Whether the second aperture
  // sees each target hit depends on the hit alone, so it is found for every lane first, apart
  // from the cell and set bookkeeping whose branches turn on cell changes (arm bench: observe's
  // CPU -1.3 %). Out of line, as Flush: inlined into ObserveOne, the lane loop kept its counters
  // on the stack beside the span loops' state (arm bench, both out of line: observe's CPU -1.2 %).
  [[gnu::noinline]] void TakePacket(const RayBatch& batch) {
    int8_t seen[RayBatch::kWidth];
    const bool ask_aperture = physical_.aperture != nullptr;
    if (ask_aperture) {
      for (int lane = 0; lane < batch.active; ++lane) {
        if (!batch.is_target[lane]) continue;  // no point (and its doubles are not set)
        seen[lane] = SeenByAperture(LanePoint(batch, lane), LaneNormal(batch, lane)) ? 1 : 0;
      }
    }
    for (int lane = 0; lane < batch.active; ++lane) {
      if (!batch.is_target[lane]) continue;
      Take(
          batch.t[lane], true,
          [&] { return Vec3(batch.dir[0][lane], batch.dir[1][lane], batch.dir[2][lane]); },
          [&] { return LaneNormal(batch, lane); }, LanePoint(batch, lane), false,
          ask_aperture ? seen[lane] : -1);
    }
  }

  // One pixel's first hit at depth t (ray direction_of(), normal normal_of(), point p where it
  // is a target); `flying`: the flying-pixel filter drops it. `seen`: SeenByAperture(p, n) when
  // known (0 or 1), else -1. The direction and normal are made only where the quality filter or
  // SeenByAperture reads them (made for every hit, their doubles were stored and never read).
  template <class DirectionOf, class NormalOf>
  void Take(float t, bool is_target, const DirectionOf& direction_of, const NormalOf& normal_of,
            const Vec3& p, bool flying, int seen = -1) {
    if (!is_target || t < sensor_.near || t > sensor_.far) return;
    // Neighbouring pixels' hits mostly share a cell: the last hit's index is tried first, and
    // when it is the cell its key is known (it fitted).
    // Its index in R is looked up once, for every set the hit goes to.
    const VoxelIndex index = cell_of_.Near(p, last_cell_, last_cell_below_);
    if (index != last_cell_) {
      VANTAGE_CHECK(VoxelIndexFits(index));
      last_cell_ = index;
      for (int a = 0; a < 3; ++a) last_cell_below_[a] = static_cast<double>(index[a]);
      last_key_ = detail::PackFittingVoxel(index);
      last_found_ = index_.Find(last_key_);
    }
    const uint64_t key = last_key_;
    const int64_t found = last_found_;
    bool passes = true;
    if (quality_.max_incidence_deg) {
      const Vec3 d = direction_of(), n = normal_of();
      const double norms = d.norm() * n.norm();
      passes = norms > 0 && std::abs(d.dot(n)) >= min_cos_incidence_ * norms;
    }
    if (passes && noise_) {
      double sigma = noise_->Sigma(t);
      if (noise_->incidence != 0) {  // Nguyen et al.'s term: grows toward grazing incidence
        const Vec3 d = direction_of(), n = normal_of();
        const double norms = d.norm() * n.norm();
        const double cos_theta = norms > 0 ? std::min(1.0, std::abs(d.dot(n)) / norms) : 0.0;
        sigma = noise_->Sigma(t, std::acos(cos_theta));
      }
      passes = sigma <= *quality_.max_depth_noise;
    }
    if (!physical_.active()) {
      Count(key, found, passes);
      return;
    }
    if (passes) ideal_keys_.Add(key, found);
    if (flying) return;
    if (!physical_.aperture) {
      Count(key, found, passes);
      return;
    }
    // Stereo cannot match nearer than its disparity search reaches; the aperture must have the
    // point in its field and lie on the side of the surface the camera sees.
    if (t < physical_.nearest) return;
    if (!(seen < 0 ? SeenByAperture(p, normal_of()) : seen != 0)) return;
    const Vec3 segment = p - physical_.centre;
    for (int a = 0; a < 3; ++a) segments_.dir[a][queued_] = static_cast<float>(segment[a]);
    segments_.query[queued_] = true;
    passes_[queued_] = passes;
    queued_keys_[queued_] = key;
    queued_found_[queued_] = found;
    if (++queued_ == OcclusionBatch::kWidth) Flush();
  }

  // Whether the second aperture has the target point p (surface normal n) in its field, on the
  // side of the surface the camera sees.
  bool SeenByAperture(const Vec3& p, const Vec3& n) const {
    const Vec3 p_body = world_from_body_.transpose() * (p - origin_);
    if (!aperture_field_->Contains(p_body)) return false;
    return n.dot(physical_.centre - p) * n.dot(origin_ - p) > 0;
  }
  static Vec3 LanePoint(const RayBatch& batch, int lane) {
    return Vec3(batch.point[0][lane], batch.point[1][lane], batch.point[2][lane]);
  }
  static Vec3 LaneNormal(const RayBatch& batch, int lane) {
    return Vec3(batch.normal[0][lane], batch.normal[1][lane], batch.normal[2][lane]);
  }

  // The cells collected, split by R, into the observation.
  void Finish() {
    Flush();
    Observation& o = *observation_;
    if (!quality_.active()) {
      o.quality_pixels = o.target_pixels;
      keys_.Take(&o.reference_indices, count_ ? &o.reference_hits : nullptr, &o.outside_keys);
    } else {
      quality_keys_.Take(&o.reference_indices, count_ ? &o.reference_hits : nullptr,
                         &o.outside_keys);
      keys_.Take(&o.plain_reference_indices, nullptr, nullptr);
    }
    if (physical_.active()) {
      ideal_keys_.Take(&o.ideal_reference_indices, nullptr, nullptr);
      o.ideal_differs = o.ideal_reference_indices != o.reference_indices;
      if (!o.ideal_differs) o.ideal_reference_indices.clear();
    }
  }

 private:
  void Count(uint64_t key, int64_t found, bool passes) {
    ++observation_->target_pixels;
    if (AddToSets(key, found, passes)) ++observation_->quality_pixels;
  }
  // Count's sets, without the pixel totals; whether the pixel passed the quality filter.
  bool AddToSets(uint64_t key, int64_t found, bool passes) {
    keys_.Add(key, found);
    if (!quality_.active() || !passes) return false;
    quality_keys_.Add(key, found);
    return true;
  }

  // The queued segments as one occlusion packet; the unoccluded ones count.
  [[gnu::noinline]] void Flush() {
    if (queued_ == 0) return;
    for (int lane = queued_; lane < OcclusionBatch::kWidth; ++lane) segments_.query[lane] = false;
    if (placed_ != nullptr)
      placed_->Occluded(&segments_);
    else
      rays_.Occluded(&segments_);
    // The totals summed here and added once: through observation_ they were read and written
    // back on every pixel (the sets' stores may alias them).
    uint64_t lit = 0, lit_passing = 0;
    for (int lane = 0; lane < queued_; ++lane) {
      if (segments_.occluded[lane]) continue;
      ++lit;
      if (AddToSets(queued_keys_[lane], queued_found_[lane], passes_[lane])) ++lit_passing;
    }
    observation_->target_pixels += lit;
    observation_->quality_pixels += lit_passing;
    queued_ = 0;
  }

  const RayScene& rays_;
  const PlacedRayScene* placed_;
  const SensorType& sensor_;
  const Mat3 world_from_body_;
  const Vec3 origin_;
  const detail::CellOfPoint cell_of_;
  const QualityFilter& quality_;
  const double min_cos_incidence_;
  const DepthNoise* noise_;
  const PhysicalModel physical_;
  const std::optional<ApertureField> aperture_field_;  // set when physical_.aperture is
  const bool count_;
  Observation* observation_;
  // keys: every measured pixel's cell; quality_keys: those passing the filter; ideal_keys: as
  // the ideal pinhole counts (the filter's pixels when one is on), with the physical model only.
  detail::CellSet &keys_, &quality_keys_, &ideal_keys_;
  const detail::CellIndex& index_;
  // The last hit's cell, its key and its index in R (a cell that fits; any such cell to start).
  VoxelIndex last_cell_{0, 0, 0};
  std::array<double, 3> last_cell_below_{0, 0, 0};  // last_cell_ as doubles (Near's guess)
  uint64_t last_key_ = detail::PackFittingVoxel(VoxelIndex{0, 0, 0});
  int64_t last_found_ = index_.Find(last_key_);
  OcclusionBatch segments_;
  int queued_ = 0;
  bool passes_[OcclusionBatch::kWidth];
  uint64_t queued_keys_[OcclusionBatch::kWidth];
  int64_t queued_found_[OcclusionBatch::kWidth];
};

// The body-frame ray of every pixel of a camera, as PixelRayInBody makes it: (1, -right(u),
// -down(v)) from PixelRight and PixelDown, each quotient computed once per column or row instead
// of once per pixel (the same functions, so the same doubles and the same float rays).
class PixelRays {
 public:
  explicit PixelRays(const SensorType& s) : sensor_(s), right_(static_cast<size_t>(s.width)) {
    for (int u = 0; u < s.width; ++u) right_[static_cast<size_t>(u)] = PixelRight(s, u);
  }
  double Down(int v) const { return PixelDown(sensor_, v); }
  Vec3 InBody(int u, double down) const { return Vec3(1.0, -right_[static_cast<size_t>(u)], -down); }

 private:
  const SensorType& sensor_;
  std::vector<double> right_;
};

// One packet of a camera's rays: pixels u_start .. u_start + active - 1 of row v, traced in the
// scene, or in `placed` (the scene with the arm carrying the camera as it stands, issue 45).
void TracePacket(const RayScene& rays, const PlacedRayScene* placed, const PixelRays& pixels,
                 const Mat3& world_from_body, int v, int u_start, RayBatch* batch) {
  const double down = pixels.Down(v);
  for (int lane = 0; lane < batch->active; ++lane) {
    const Vec3 d = world_from_body * pixels.InBody(u_start + lane, down);
    for (int a = 0; a < 3; ++a) batch->dir[a][lane] = static_cast<float>(d[a]);
  }
  if (placed) {
    placed->Intersect(batch);
  } else {
    rays.Intersect(batch);
  }
}

// One image row's first hits, for the pixels traced in it (the flying-pixel filter compares each
// pixel with its 4-neighbours, so it holds three rows).
struct RowHits {
  int v = -1;
  std::vector<float> t;  // NaN: not traced; inf: no surface within range
  std::vector<uint8_t> is_target;
  std::vector<std::array<float, 3>> dir, normal;
  std::vector<std::array<double, 3>> point;
};

// Spans merged per row, sorted, overlapping or touching ones joined.
std::vector<std::pair<int, int>> Merged(std::vector<std::pair<int, int>> spans) {
  std::sort(spans.begin(), spans.end());
  std::vector<std::pair<int, int>> out;
  for (const auto& [u0, u1] : spans) {
    if (!out.empty() && u0 <= out.back().second + 1) {
      out.back().second = std::max(out.back().second, u1);
    } else {
      out.emplace_back(u0, u1);
    }
  }
  return out;
}

// With a flying-pixel threshold (time of flight, issue 43): a pixel is dropped where a
// 4-neighbour's surface lies more than the threshold nearer or farther, as the sensors' own
// filters do. A neighbour whose ray meets no surface within range returns no light to mix and is
// ignored; neighbours off the image do not exist. Rows are traced in order, each over the pixels
// judged in it and beside them (one pixel wider) and those judged in the rows above and below:
// the extra rays are the spans' borders only.
void ObserveWithFlyingFilter(const RayScene& rays, const Candidate& candidate,
                             const std::vector<RowSpan>& spans, const PlacedRayScene* placed,
                             double threshold, RayBatch* batch, Observation* observation,
                             PixelJudge* judge) {
  const SensorType& s = candidate.sensor;
  if (spans.empty()) return;
  const Mat3 world_from_body = candidate.world_from_body.rotation.toRotationMatrix();
  const PixelRays pixels(s);
  const int first = spans.front().v, last = spans.back().v;
  // Rows first - 1 .. last + 1: the judged spans and the spans to trace.
  const auto slot = [&](int v) { return static_cast<size_t>(v - first + 1); };
  std::vector<std::vector<std::pair<int, int>>> judged(static_cast<size_t>(last - first + 3));
  for (const RowSpan& span : spans) judged[slot(span.v)].emplace_back(span.u0, span.u1);
  const auto needed = [&](int v) {
    std::vector<std::pair<int, int>> out;
    for (const auto& [u0, u1] : judged[slot(v)]) out.emplace_back(std::max(u0 - 1, 0), std::min(u1 + 1, s.width - 1));
    for (const int w : {v - 1, v + 1}) {
      if (w < first || w > last) continue;
      for (const auto& span : judged[slot(w)]) out.push_back(span);
    }
    return Merged(std::move(out));
  };
  std::array<RowHits, 3> ring;
  const auto trace_row = [&](int v) -> const RowHits* {
    if (v < 0 || v >= s.height) return nullptr;
    RowHits& row = ring[static_cast<size_t>(v % 3)];
    if (row.v == v) return &row;
    row.v = v;
    row.t.assign(static_cast<size_t>(s.width), std::numeric_limits<float>::quiet_NaN());
    row.is_target.resize(static_cast<size_t>(s.width));
    row.dir.resize(static_cast<size_t>(s.width));
    row.normal.resize(static_cast<size_t>(s.width));
    row.point.resize(static_cast<size_t>(s.width));
    for (const auto& [u0, u1] : needed(v)) {
      for (int u_start = u0; u_start <= u1; u_start += RayBatch::kWidth) {
        batch->active = std::min(RayBatch::kWidth, u1 - u_start + 1);
        TracePacket(rays, placed, pixels, world_from_body, v, u_start, batch);
        observation->rays_traced += static_cast<uint64_t>(batch->active);
        for (int lane = 0; lane < batch->active; ++lane) {
          const size_t u = static_cast<size_t>(u_start + lane);
          row.t[u] = batch->t[lane];
          row.is_target[u] = batch->is_target[lane] ? 1 : 0;
          for (int a = 0; a < 3; ++a) {
            row.dir[u][a] = batch->dir[a][lane];
            if (!std::isinf(batch->t[lane])) row.normal[u][a] = batch->normal[a][lane];
            if (batch->is_target[lane]) row.point[u][a] = batch->point[a][lane];
          }
        }
      }
    }
    return &row;
  };
  // A neighbour's depth differs by more than the threshold (a traced neighbour with a surface).
  const auto steps = [&](const RowHits* row, int u, float t) {
    if (!row || u < 0 || u >= s.width) return false;
    const float other = row->t[static_cast<size_t>(u)];
    return std::isfinite(other) && std::abs(static_cast<double>(other) - t) > threshold;
  };
  for (int v = first; v <= last; ++v) {
    const RowHits* above = trace_row(v - 1);
    const RowHits* row = trace_row(v);
    const RowHits* below = trace_row(v + 1);
    for (const auto& [u0, u1] : judged[slot(v)]) {
      for (int u = u0; u <= u1; ++u) {
        const size_t i = static_cast<size_t>(u);
        const float t = row->t[i];
        if (!row->is_target[i]) continue;
        const bool flying = steps(row, u - 1, t) || steps(row, u + 1, t) || steps(above, u, t) ||
                            steps(below, u, t);
        const auto& d = row->dir[i];
        const auto& n = row->normal[i];
        const auto& p = row->point[i];
        judge->Take(
            t, true, [&] { return Vec3(d[0], d[1], d[2]); }, [&] { return Vec3(n[0], n[1], n[2]); },
            Vec3(p[0], p[1], p[2]), flying);
      }
    }
  }
}

Observation ObserveOne(const RayScene& rays, const Reference& reference,
                       const detail::CellIndex& index, const Candidate& candidate,
                       const std::vector<Aabb>& blocks, const ObserveOptions& options,
                       const detail::ArmOcclusion& arms, detail::CellSetsPool* pool) {
  const std::vector<RowSpan> spans = SpansToTrace(candidate, blocks, options.cull);
  // A camera on an arm sees the cell with the arm as it stands in this view: one top-level BVH
  // over the cell and the instances of the links its rays can meet, built here (a handful of
  // boxes) and dropped after; the cell alone where they can meet none.
  std::optional<PlacedRayScene> placed;
  if (candidate.arm) placed = arms.PlaceForView(candidate, spans);
  const PlacedRayScene* placed_rays = placed ? &*placed : nullptr;
  const SensorType& s = candidate.sensor;
  const Mat3 world_from_body = candidate.world_from_body.rotation.toRotationMatrix();
  const PixelRays pixels(s);
  const Vec3 origin = candidate.world_from_body.position;
  Observation observation;
  const detail::CellSetsPool::Lease sets(pool);
  PixelJudge judge(rays, placed_rays, candidate, reference, index, options, &*sets, &observation);

  RayBatch batch;
  for (int a = 0; a < 3; ++a) batch.origin[a] = static_cast<float>(origin[a]);
  // The direction's body-x component is 1, so the hit parameter t is the depth itself.
  batch.tfar = std::nextafter(static_cast<float>(s.far), std::numeric_limits<float>::infinity());

  if (const std::optional<double> flying = judge.physical().flying) {
    ObserveWithFlyingFilter(rays, candidate, spans, placed_rays, *flying, &batch, &observation,
                            &judge);
  } else {
    for (const RowSpan& span : spans) {
      for (int u_start = span.u0; u_start <= span.u1; u_start += RayBatch::kWidth) {
        batch.active = std::min(RayBatch::kWidth, span.u1 - u_start + 1);
        TracePacket(rays, placed_rays, pixels, world_from_body, span.v, u_start, &batch);
        observation.rays_traced += static_cast<uint64_t>(batch.active);
        judge.TakePacket(batch);
      }
    }
  }
  judge.Finish();
  return observation;
}

}  // namespace

std::vector<Observation> Observe(const RayScene& rays, const Reference& reference,
                                 std::span<const Candidate> candidates, const ObserveOptions& options) {
  for (const Candidate& c : candidates) CheckCandidate(c, c.name);
  options.Validate();
  const std::vector<Aabb> blocks = ReferenceBlocks(reference);
  const detail::ArmOcclusion arms(rays, candidates);
  const detail::CellIndex index(reference.keys);
  detail::CellSetsPool pool;
  std::vector<Observation> observations(candidates.size());
  std::atomic<size_t> done{0};
  // Candidates are independent; each fills its own slot, so the result does not depend on the
  // thread count or the order of completion.
  tbb::parallel_for(size_t{0}, candidates.size(), [&](size_t i) {
    if (InterruptRequested()) return;  // the rest is skipped; thrown once the loop is left
    observations[i] = ObserveOne(rays, reference, index, candidates[i], blocks, options, arms, &pool);
    const size_t finished = ++done;
    if (options.progress) options.progress(finished, candidates.size());
  });
  ThrowIfInterrupted();
  return observations;
}

std::vector<uint64_t> CountRaysToTrace(const Reference& reference,
                                       std::span<const Candidate> candidates,
                                       const ObserveOptions& options) {
  const std::vector<Aabb> blocks = ReferenceBlocks(reference);
  std::vector<uint64_t> rays(candidates.size(), 0);
  tbb::parallel_for(size_t{0}, candidates.size(), [&](size_t i) {
    for (const RowSpan& span : SpansToTrace(candidates[i], blocks, options.cull))
      rays[i] += static_cast<uint64_t>(span.u1 - span.u0 + 1);
  });
  return rays;
}

std::vector<Observation> Observe(const Scene& scene, const Reference& reference,
                                 std::span<const Candidate> candidates, const ObserveOptions& options) {
  return Observe(RayScene(scene), reference, candidates, options);
}

}  // namespace vantage
