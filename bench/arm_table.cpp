// The arm benchmark of issue 45 (bench/arm_table.sh writes the scene and runs this): a 6-axis
// arm in a cell of about 50 k triangles. Times, each on all cores:
//   IK          inverse kinematics of a `reach:` region's poses (SolveIk, as ApplyArms calls it);
//   collision   the FCL checks of a kind-`arm` population's joint-space views (ArmCollisions);
//   observe     vantage's Observe of the collision-free views, the arm occluding its camera,
//   limit       the ray-casting limit loop on the same views (the culled pixels, no voxels, no
//               sets, no arm), as bench/ray_limit.cpp; and the same loop with each view's arm
//               placed in the scene (observe's PlacedRayScene: the rays a view must trace);
//   same rays   the limit loop casting exactly the rays observe's model asks for: the culled
//               pixels' primary rays and, from each target hit the second aperture sees (the
//               D435's projector), its occlusion segment, 16 to a packet, against the same
//               scene (the cell alone, or each view's arm placed); the segments are found in an
//               untimed pass first, so the loop times the ray casting only;
//   (each of observe and the same-rays loops also in CPU seconds, user + system: cpu_*)
//   tour        Held–Karp on 10 views (exact) and --cycle-time's greedy over all views.
// Usage: arm_table SCENE [CYCLE_SECONDS]  -> one JSON line on stdout. With ARM_TABLE_ROUNDS=R
// only observe and the same-rays loops, R rounds interleaved, least CPU seconds of each.
#include <sys/resource.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>

#include "limit_loops.hpp"
#include "observe/arm_occlusion.hpp"
#include "observe/culling.hpp"
#include "vantage/arm.hpp"
#include "vantage/ray_scene.hpp"
#include "vantage/tour.hpp"
#include "vantage/vantage.hpp"

namespace {
double Since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}
// The process's CPU seconds (user + system, all threads): unlike wall time, it does not grow
// when other processes share the cores, so the observe / same-rays ratios stay comparable on a
// loaded machine.
double CpuSeconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  const auto seconds = [](const timeval& t) { return static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec); };
  return seconds(usage.ru_utime) + seconds(usage.ru_stime);
}
}  // namespace

int main(int argc, char** argv) {
  using namespace vantage;
  if (argc < 2) {
    std::fprintf(stderr, "usage: arm_table SCENE [CYCLE_SECONDS]\n");
    return 2;
  }
  const double cycle = argc > 2 ? std::stod(argv[2]) : 10.0;
  try {
    const Problem problem = LoadProblem(argv[1], {});
    DeployOptions deploy{problem.observation_point, problem.random_roll, problem.seed};
    const std::vector<Candidate> deployed =
        DeployCandidates(problem.populations, problem.sensors, problem.sensor_types, deploy);
    const Population* reach = nullptr;
    const Population* joint_space = nullptr;
    uint32_t joint_space_index = 0;  // as ApplyArms numbers it: its place among the populations
    for (uint32_t i = 0; i < problem.populations.size(); ++i) {
      const Population& p = problem.populations[i];
      if (p.arm && p.arm_views) joint_space = &p, joint_space_index = i;
      if (p.arm && !p.arm_views) reach = &p;
    }
    if (!reach || !joint_space) throw InputError("the scene needs a reach: and an arm population");
    const PlacedRobot& robot = problem.robots.front();

    // IK: the region's poses, as ApplyArms solves them.
    const ArmKinematics reach_kinematics(robot, reach->arm->link, reach->arm->joints);
    std::vector<const Candidate*> poses;
    for (const Candidate& c : deployed)
      if (c.population == reach->name) poses.push_back(&c);
    std::atomic<size_t> reached{0};
    auto start = std::chrono::steady_clock::now();
    tbb::parallel_for(size_t{0}, poses.size(), [&](size_t k) {
      const auto q = reach_kinematics.SolveIk(
          poses[k]->world_from_body, reach->arm->link_from_camera, ArmKinematics::Match::kDirection,
          reach->arm->position_tolerance, reach->arm->angle_tolerance, reach_kinematics.Rest(),
          reach->arm->ik_restarts, problem.seed, k);
      if (q) ++reached;
    });
    const double ik_seconds = Since(start);

    // Collision: the joint-space views.
    const ArmKinematics kinematics(robot, joint_space->arm->link, joint_space->arm->joints);
    std::vector<std::string> moving;
    for (size_t i : kinematics.moved()) moving.push_back(kinematics.joint_names()[i]);
    start = std::chrono::steady_clock::now();
    const ArmCollisions collisions(robot, problem.scene, problem.mounting.keep_out, moving,
                                   joint_space->arm->allowed_pairs);
    const double collision_build_seconds = Since(start);
    const std::vector<std::vector<double>> drawn =
        DrawConfigurations(*joint_space, kinematics, problem.seed, joint_space_index);
    std::vector<char> free(drawn.size(), 0);
    start = std::chrono::steady_clock::now();
    tbb::parallel_for(size_t{0}, drawn.size(), [&](size_t k) {
      free[k] = collisions.Check(kinematics.LinkPosesAt(drawn[k])) == ArmCollision::kNone;
    });
    const double collision_seconds = Since(start);

    // The views as vantage makes them (ApplyArms: both populations, IK and collisions again),
    // the robot's links out of the ray scene (the pipeline's ApplyArmPopulations).
    start = std::chrono::steady_clock::now();
    const ArmViews views = ApplyArms(problem, deployed, problem.seed);
    const double apply_seconds = Since(start);
    Scene cell;
    for (const SceneObject& object : problem.scene.objects)
      if (object.name.rfind(robot.name + "::", 0) != 0) cell.objects.push_back(object);
    const Reference reference = BuildReference(cell, {problem.cell_size});
    const RayScene rays(cell);
    ObserveOptions options;
    start = std::chrono::steady_clock::now();
    double cpu = CpuSeconds();
    const std::vector<Observation> observations = Observe(rays, reference, views.candidates, options);
    const double observe_seconds = Since(start);
    const double observe_cpu = CpuSeconds() - cpu;
    // The same views without the arm's links: what the arm's occlusion adds.
    std::vector<Candidate> bare = views.candidates;
    for (Candidate& c : bare) c.arm = nullptr;
    start = std::chrono::steady_clock::now();
    cpu = CpuSeconds();
    const std::vector<Observation> bare_observations = Observe(rays, reference, bare, options);
    const double observe_bare_seconds = Since(start);
    const double observe_bare_cpu = CpuSeconds() - cpu;

    // The limit loop on the same views: the culled pixels, traced and nothing else.
    const std::vector<Aabb> blocks = detail::ReferenceBlocks(reference);
    std::vector<std::vector<detail::RowSpan>> spans(views.candidates.size());
    uint64_t traced = 0;
    for (size_t i = 0; i < spans.size(); ++i) {
      spans[i] = detail::SpansToTrace(views.candidates[i], blocks, true);
      for (const auto& s : spans[i]) traced += static_cast<uint64_t>(s.u1 - s.u0 + 1);
    }
    // The limit loop of one view: its spans' pixel rays, 16 at a time, into `intersect`.
    const auto trace_view = [&](size_t i, const auto& intersect) {
      bench::TraceSpans(views.candidates[i], spans[i], intersect);
    };
    start = std::chrono::steady_clock::now();
    tbb::parallel_for(size_t{0}, views.candidates.size(), [&](size_t i) {
      trace_view(i, [&](RayBatch* batch) { rays.Intersect(batch); });
    });
    const double limit_seconds = Since(start);
    // The same loop in each view's scene with its arm placed (a top-level BVH per view).
    start = std::chrono::steady_clock::now();
    const detail::ArmOcclusion arms(rays, views.candidates);
    tbb::parallel_for(size_t{0}, views.candidates.size(), [&](size_t i) {
      const Candidate& c = views.candidates[i];
      std::optional<PlacedRayScene> placed;
      if (c.arm) placed.emplace(arms.Place(*c.arm));
      trace_view(i, [&](RayBatch* batch) {
        if (placed) {
          placed->Intersect(batch);
        } else {
          rays.Intersect(batch);
        }
      });
    });
    const double limit_arm_seconds = Since(start);

    // The same rays as observe's model: each view's occlusion segments, found in an untimed pass
    // (the conditions of observe.cpp's PixelJudge::Take), then cast with the primary rays.
    const auto find_segments = [&](bool with_arm) {
      std::vector<bench::Segments> all(views.candidates.size());
      tbb::parallel_for(size_t{0}, views.candidates.size(), [&](size_t i) {
        const Candidate& c = views.candidates[i];
        std::optional<PlacedRayScene> placed;
        if (with_arm && c.arm) placed.emplace(arms.Place(*c.arm));
        all[i] = bench::FindSegments(c, spans[i], [&](RayBatch* batch) {
          if (placed) {
            placed->Intersect(batch);
          } else {
            rays.Intersect(batch);
          }
        });
      });
      return all;
    };
    // Primary packets and segment packets of every view, into `scene_of(i)`'s Intersect and
    // Occluded.
    // `with_arm`: 0 the cell alone, 1 every link placed (Place), 2 the links the view's rays can
    // meet (PlaceForView, as observe places them).
    const auto same_rays = [&](const std::vector<bench::Segments>& segments, int with_arm) {
      tbb::parallel_for(size_t{0}, views.candidates.size(), [&](size_t i) {
        const Candidate& c = views.candidates[i];
        std::optional<PlacedRayScene> placed;
        if (with_arm == 1 && c.arm) placed.emplace(arms.Place(*c.arm));
        if (with_arm == 2 && c.arm) placed = arms.PlaceForView(c, spans[i]);
        trace_view(i, [&](RayBatch* batch) {
          if (placed) {
            placed->Intersect(batch);
          } else {
            rays.Intersect(batch);
          }
        });
        bench::CastSegments(segments[i], [&](OcclusionBatch* packet) {
          if (placed) {
            placed->Occluded(packet);
          } else {
            rays.Occluded(packet);
          }
        });
      });
    };
    const std::vector<bench::Segments> bare_segments = find_segments(false);
    const std::vector<bench::Segments> arm_segments = find_segments(true);
    uint64_t bare_segment_count = 0, arm_segment_count = 0;
    for (size_t i = 0; i < views.candidates.size(); ++i) {
      bare_segment_count += bare_segments[i].dir.size();
      arm_segment_count += arm_segments[i].dir.size();
    }
    // ARM_TABLE_ROUNDS=R: R more rounds of observe and the same-rays loop, interleaved, and the
    // least CPU seconds of each over all rounds (the first round's included), for a ratio that a
    // busy machine does not move much.
    if (const char* env = std::getenv("ARM_TABLE_ROUNDS")) {
      const int rounds = std::max(1, std::atoi(env));
      double best[4] = {observe_cpu, observe_bare_cpu, 1e300, 1e300};
      for (int r = 0; r < rounds; ++r) {
        const auto time = [&](double* least, const auto& work) {
          const double before = CpuSeconds();
          work();
          *least = std::min(*least, CpuSeconds() - before);
        };
        time(&best[0], [&] { Observe(rays, reference, views.candidates, options); });
        time(&best[2], [&] { same_rays(arm_segments, 2); });
        time(&best[1], [&] { Observe(rays, reference, bare, options); });
        time(&best[3], [&] { same_rays(bare_segments, 0); });
      }
      std::printf(
          "{\"reference_cells\": %zu, \"rounds\": %d, \"cpu_observe\": %.3f, \"cpu_same_rays_links_culled\": %.3f, "
          "\"cpu_observe_over_same_rays_culled\": %.3f, \"cpu_observe_without_arm\": %.3f, "
          "\"cpu_same_rays\": %.3f, \"cpu_observe_without_arm_over_same_rays\": %.3f}\n",
          reference.size(), rounds, best[0], best[2], best[0] / best[2], best[1], best[3], best[1] / best[3]);
      return 0;
    }
    start = std::chrono::steady_clock::now();
    cpu = CpuSeconds();
    same_rays(bare_segments, 0);
    const double same_rays_seconds = Since(start);
    const double same_rays_cpu = CpuSeconds() - cpu;
    start = std::chrono::steady_clock::now();
    same_rays(arm_segments, 1);
    const double same_rays_arm_seconds = Since(start);
    start = std::chrono::steady_clock::now();
    cpu = CpuSeconds();
    same_rays(arm_segments, 2);
    const double same_rays_culled_seconds = Since(start);
    const double same_rays_culled_cpu = CpuSeconds() - cpu;
    size_t views_with_links = 0;
    for (size_t i = 0; i < views.candidates.size(); ++i)
      if (views.candidates[i].arm && arms.PlaceForView(views.candidates[i], spans[i]))
        ++views_with_links;

    // Tours: straight-line times among the views and home (URDF speeds).
    const ArmSetup& arm = views.arms.front();
    const size_t n = views.candidates.size();
    const auto configuration = [&](size_t k) -> const std::vector<double>& {
      return k == n ? arm.home : views.candidates[k].arm->joints;
    };
    start = std::chrono::steady_clock::now();
    TourTimes times;
    times.motion.assign(n + 1, std::vector<double>(n + 1, 0.0));
    tbb::parallel_for(size_t{0}, n + 1, [&](size_t a) {
      for (size_t b = 0; b <= n; ++b)
        times.motion[a][b] = MotionSeconds(configuration(a), configuration(b), arm.speeds);
    });
    for (const Candidate& c : views.candidates)
      times.acquisition.push_back(c.sensor.fps > 0 ? 1.0 / c.sensor.fps : 0.0);
    const double times_seconds = Since(start);
    // Ten views of the region (those IK reached), spread over it.
    std::vector<uint32_t> region_views;
    for (uint32_t k = 0; k < n; ++k)
      if (views.candidates[k].population == reach->name) region_views.push_back(k);
    std::vector<uint32_t> ten;
    for (size_t k = 0; k < 10 && k < region_views.size(); ++k)
      ten.push_back(region_views[k * region_views.size() / 10]);
    start = std::chrono::steady_clock::now();
    const Tour tour = SolveTour(times, ten);
    const double tour_seconds = Since(start);
    start = std::chrono::steady_clock::now();
    size_t colliding_moves = 0;
    size_t at = n;
    std::vector<uint32_t> stops = tour.order;
    stops.push_back(static_cast<uint32_t>(n));
    std::vector<std::pair<size_t, size_t>> colliding;
    for (uint32_t next : stops) {
      if (!StraightMotionIsFree(*arm.kinematics, *arm.collisions, configuration(at),
                                configuration(next), 0.01)) {
        ++colliding_moves;
        colliding.emplace_back(at, next);
      }
      at = next;
    }
    const double tour_check_seconds = Since(start);
    // The colliding moves planned around (OMPL), as the pipeline does.
    size_t planned = 0;
    start = std::chrono::steady_clock::now();
    for (const auto& [a, b] : colliding) {
      MotionPlanOptions plan;
      plan.seed = problem.seed;
      plan.stream = (uint64_t{a} << 32) | b;
      planned += PlanMotion(*arm.kinematics, *arm.collisions, configuration(a), configuration(b),
                            arm.speeds, plan).found ? 1 : 0;
    }
    const double plan_seconds = Since(start);
    start = std::chrono::steady_clock::now();
    const CycleTimeResult cycle_result =
        MostCoverageWithinCycleTime(times, observations, reference.size(), cycle);
    const double cycle_seconds = Since(start);

    std::printf(
        "{\"triangles\": %zu, \"reach_poses\": %zu, \"reached\": %zu, \"ik_seconds\": %.3f, "
        "\"drawn\": %zu, \"collision_free\": %zu, \"collision_build_seconds\": %.3f, "
        "\"collision_seconds\": %.3f, \"apply_arms_seconds\": %.3f, \"views\": %zu, \"observe_seconds\": %.3f, \"observe_without_arm_seconds\": %.3f, "
        "\"limit_rays\": %llu, \"limit_seconds\": %.3f, \"observe_over_limit\": %.3f, "
        "\"limit_with_arm_seconds\": %.3f, \"observe_over_limit_with_arm\": %.3f, "
        "\"observe_without_arm_over_limit\": %.3f, "
        "\"segments\": %llu, \"segments_with_arm\": %llu, \"limit_same_rays_seconds\": %.3f, "
        "\"limit_same_rays_with_arm_seconds\": %.3f, \"observe_over_same_rays_with_arm\": %.3f, "
        "\"limit_same_rays_links_culled_seconds\": %.3f, \"observe_over_same_rays_culled\": %.3f, "
        "\"views_with_links_placed\": %zu, "
        "\"observe_without_arm_over_same_rays\": %.3f, "
        "\"cpu_observe\": %.3f, \"cpu_observe_without_arm\": %.3f, \"cpu_same_rays\": %.3f, "
        "\"cpu_same_rays_links_culled\": %.3f, \"cpu_observe_over_same_rays_culled\": %.3f, "
        "\"cpu_observe_without_arm_over_same_rays\": %.3f, "
        "\"motion_table_seconds\": %.3f, \"tour10_seconds\": %.6f, \"tour10_method\": \"%s\", "
        "\"tour10_total_s\": %.3f, \"tour10_check_seconds\": %.3f, \"tour10_colliding_moves\": %zu, "
        "\"tour10_planned\": %zu, \"tour10_plan_seconds\": %.3f, "
        "\"cycle_time\": %.1f, \"cycle_views\": %zu, \"cycle_coverage\": %.4f, "
        "\"cycle_tour_s\": %.3f, \"cycle_seconds\": %.3f}\n",
        cell.TriangleCount(), poses.size(), reached.load(), ik_seconds, drawn.size(),
        static_cast<size_t>(std::count(free.begin(), free.end(), 1)), collision_build_seconds,
        collision_seconds, apply_seconds, n, observe_seconds, observe_bare_seconds, static_cast<unsigned long long>(traced),
        limit_seconds, observe_seconds / limit_seconds, limit_arm_seconds,
        observe_seconds / limit_arm_seconds, observe_bare_seconds / limit_seconds,
        static_cast<unsigned long long>(bare_segment_count),
        static_cast<unsigned long long>(arm_segment_count), same_rays_seconds,
        same_rays_arm_seconds, observe_seconds / same_rays_arm_seconds, same_rays_culled_seconds,
        observe_seconds / same_rays_culled_seconds, views_with_links,
        observe_bare_seconds / same_rays_seconds, observe_cpu, observe_bare_cpu, same_rays_cpu,
        same_rays_culled_cpu, observe_cpu / same_rays_culled_cpu, observe_bare_cpu / same_rays_cpu,
        times_seconds, tour_seconds,
        tour.method.c_str(), tour.total_seconds, tour_check_seconds, colliding_moves, planned,
        plan_seconds, cycle,
        cycle_result.chosen.size(), cycle_result.coverage, cycle_result.tour.total_seconds,
        cycle_seconds);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
  }
}
