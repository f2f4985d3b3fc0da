#include "vantage/ray_scene.hpp"

#include <embree3/rtcore.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>

#include "vantage/error.hpp"

namespace vantage {

struct RayScene::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::vector<uint8_t> is_target;  // by geometry id
  std::vector<int32_t> object;     // by geometry id: index into Scene::objects
  // By geometry id, targets only: the mesh in double, for RayBatch::point.
  std::vector<const TriangleMesh*> target_mesh;
  std::vector<TriangleMesh> target_meshes;  // owned copies (the scene may not outlive this)
  std::vector<std::array<size_t, 2>> sizes;  // by geometry id: vertices, triangles

  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

namespace {

void ReportEmbreeError(void* /*user*/, RTCError code, const char* message) {
  spdlog::error("embree error {}: {}", static_cast<int>(code), message);
}

/// The point at Embree's barycentric coordinates (u, v) on the scene's own double triangle,
/// v0 + u (v1 - v0) + v (v2 - v0): exact on a face that lies on a grid plane.
Vec3 TargetPoint(const TriangleMesh& mesh, unsigned triangle, float u, float v) {
  const auto& corners = mesh.triangles[triangle];
  const Vec3& v0 = mesh.vertices[corners[0]];
  return v0 + static_cast<double>(u) * (mesh.vertices[corners[1]] - v0) +
         static_cast<double>(v) * (mesh.vertices[corners[2]] - v0);
}

}  // namespace

RayScene::RayScene(const Scene& scene) : impl_(std::make_unique<Impl>()) {
  impl_->device = rtcNewDevice(nullptr);
  if (!impl_->device) throw InternalError("cannot create the Embree device");
  rtcSetDeviceErrorFunction(impl_->device, ReportEmbreeError, nullptr);
  impl_->scene = rtcNewScene(impl_->device);
  rtcSetSceneBuildQuality(impl_->scene, RTC_BUILD_QUALITY_HIGH);
  rtcSetSceneFlags(impl_->scene, RTC_SCENE_FLAG_ROBUST);
  size_t targets = 0;
  for (const SceneObject& object : scene.objects)
    targets += object.is_target() && !object.mesh.triangles.empty() ? 1 : 0;
  impl_->target_meshes.reserve(targets);  // target_mesh points into it
  for (size_t object_index = 0; object_index < scene.objects.size(); ++object_index) {
    const SceneObject& object = scene.objects[object_index];
    if (object.mesh.triangles.empty()) continue;
    RTCGeometry geometry = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float),
        object.mesh.vertices.size()));
    auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned),
        object.mesh.triangles.size()));
    VANTAGE_CHECK(vertices != nullptr && indices != nullptr);
    for (size_t i = 0; i < object.mesh.vertices.size(); ++i) {
      for (int a = 0; a < 3; ++a) vertices[3 * i + a] = static_cast<float>(object.mesh.vertices[i][a]);
    }
    for (size_t i = 0; i < object.mesh.triangles.size(); ++i) {
      for (int a = 0; a < 3; ++a) indices[3 * i + a] = object.mesh.triangles[i][a];
    }
    rtcCommitGeometry(geometry);
    const unsigned id = rtcAttachGeometry(impl_->scene, geometry);
    rtcReleaseGeometry(geometry);
    if (impl_->is_target.size() <= id) impl_->is_target.resize(id + 1, 0);
    impl_->is_target[id] = object.is_target() ? 1 : 0;
    if (impl_->object.size() <= id) impl_->object.resize(id + 1, -1);
    impl_->object[id] = static_cast<int32_t>(object_index);
    if (impl_->target_mesh.size() <= id) impl_->target_mesh.resize(id + 1, nullptr);
    if (impl_->sizes.size() <= id) impl_->sizes.resize(id + 1, {0, 0});
    impl_->sizes[id] = {object.mesh.vertices.size(), object.mesh.triangles.size()};
    if (object.is_target()) {
      impl_->target_meshes.push_back(object.mesh);
      impl_->target_mesh[id] = &impl_->target_meshes.back();
    }
  }
  rtcCommitScene(impl_->scene);
}

uint64_t RayScene::GeometryFingerprint() const {
  // FNV-1a over 64-bit words (a byte at a time took a second for a scene of 4 M triangles).
  uint64_t hash = 1469598103934665603ull;
  const auto mix = [&hash](const void* data, size_t bytes) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (; bytes >= 8; bytes -= 8, p += 8) {
      uint64_t word;
      std::memcpy(&word, p, 8);
      hash = (hash ^ word) * 1099511628211ull;
    }
    for (; bytes > 0; --bytes, ++p) hash = (hash ^ *p) * 1099511628211ull;
  };
  for (size_t id = 0; id < impl_->sizes.size(); ++id) {
    const RTCGeometry geometry = rtcGetGeometry(impl_->scene, static_cast<unsigned>(id));
    const auto [vertices, triangles] = impl_->sizes[id];
    const uint64_t header[] = {id, impl_->is_target[id], vertices, triangles};
    mix(header, sizeof(header));
    mix(rtcGetGeometryBufferData(geometry, RTC_BUFFER_TYPE_VERTEX, 0), vertices * 3 * sizeof(float));
    mix(rtcGetGeometryBufferData(geometry, RTC_BUFFER_TYPE_INDEX, 0), triangles * 3 * sizeof(unsigned));
    if (const TriangleMesh* mesh = impl_->target_mesh[id])  // hits on targets use the doubles
      mix(mesh->vertices.data(), mesh->vertices.size() * sizeof(Vec3));
  }
  return hash;
}

RayScene::~RayScene() = default;
RayScene::RayScene(RayScene&&) noexcept = default;
RayScene& RayScene::operator=(RayScene&&) noexcept = default;

namespace {

// The instance id of the static scene in a PlacedRayScene (attached first); the bodies follow.
constexpr unsigned kSceneInstance = 0;

// Traces the active lanes of `batch` in `scene` (a RayScene's own, or a PlacedRayScene's top
// level) and decodes the hits: geometry ids index the RayScene's tables; a hit inside a body's
// instance (instance id > kSceneInstance, only in a placed scene) is an occluder whose
// object-space normal `body_to_world[instance]` turns into the world frame.
void IntersectPacket(RTCScene scene, const std::vector<uint8_t>& is_target,
                     const std::vector<const TriangleMesh*>& target_mesh,
                     const std::vector<Mat3>* body_to_world, RayBatch* batch) {
  static_assert(RayBatch::kWidth == 16);
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  alignas(64) int valid[16];
  alignas(64) RTCRayHit16 rays;
  VANTAGE_CHECK(batch->active >= 1 && batch->active <= 16);
  for (int lane = 0; lane < 16; ++lane) {
    valid[lane] = lane < batch->active ? -1 : 0;
    // Idle lanes repeat lane 0's ray: on AVX2 machines Embree splits the 16-wide packet into two
    // 8-wide ones and asserts that every ray of a half is valid, masked or not (a stale or
    // uninitialised direction aborted bin_picking_with_occlusions.world).
    const int source = lane < batch->active ? lane : 0;
    rays.ray.org_x[lane] = batch->origin[0];
    rays.ray.org_y[lane] = batch->origin[1];
    rays.ray.org_z[lane] = batch->origin[2];
    rays.ray.dir_x[lane] = batch->dir[0][source];
    rays.ray.dir_y[lane] = batch->dir[1][source];
    rays.ray.dir_z[lane] = batch->dir[2][source];
    rays.ray.tnear[lane] = 0.0f;
    rays.ray.tfar[lane] = batch->tfar;
    rays.ray.time[lane] = 0.0f;
    rays.ray.mask[lane] = 0xFFFFFFFFu;  // Debian's Embree has ray masks on (debian-deps.md)
    rays.ray.id[lane] = static_cast<unsigned>(lane);
    rays.ray.flags[lane] = 0;
    rays.hit.geomID[lane] = RTC_INVALID_GEOMETRY_ID;
    rays.hit.instID[0][lane] = RTC_INVALID_GEOMETRY_ID;
  }
  rtcIntersect16(valid, scene, &context, &rays);
  for (int lane = 0; lane < batch->active; ++lane) {
    const unsigned geom = rays.hit.geomID[lane];
    const unsigned instance = rays.hit.instID[0][lane];
    if (geom == RTC_INVALID_GEOMETRY_ID) {
      batch->t[lane] = std::numeric_limits<float>::infinity();
      batch->is_target[lane] = false;
    } else if (body_to_world && instance != kSceneInstance) {
      VANTAGE_CHECK(instance < body_to_world->size());
      batch->t[lane] = rays.ray.tfar[lane];
      batch->is_target[lane] = false;  // a body (the carrying robot's link) occludes
      const Vec3 n = (*body_to_world)[instance] *
                     Vec3(rays.hit.Ng_x[lane], rays.hit.Ng_y[lane], rays.hit.Ng_z[lane]);
      for (int a = 0; a < 3; ++a) batch->normal[a][lane] = static_cast<float>(n[a]);
    } else {
      batch->t[lane] = rays.ray.tfar[lane];
      batch->is_target[lane] = is_target[geom] != 0;
      batch->normal[0][lane] = rays.hit.Ng_x[lane];
      batch->normal[1][lane] = rays.hit.Ng_y[lane];
      batch->normal[2][lane] = rays.hit.Ng_z[lane];
      if (batch->is_target[lane]) {
        const Vec3 point = TargetPoint(*target_mesh[geom], rays.hit.primID[lane],
                                       rays.hit.u[lane], rays.hit.v[lane]);
        for (int a = 0; a < 3; ++a) batch->point[a][lane] = point[a];
      }
    }
  }
}

// Tests the queried lanes of `batch` for any hit in `scene`.
void OccludedPacket(RTCScene scene, OcclusionBatch* batch) {
  static_assert(OcclusionBatch::kWidth == 16);
  int first = -1;
  for (int lane = 0; lane < 16 && first < 0; ++lane) first = batch->query[lane] ? lane : -1;
  if (first < 0) return;
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  alignas(64) int valid[16];
  alignas(64) RTCRay16 rays;
  for (int lane = 0; lane < 16; ++lane) {
    valid[lane] = batch->query[lane] ? -1 : 0;
    // Idle lanes repeat a queried lane's segment (Embree's AVX2 halves check every ray; see
    // IntersectPacket).
    const int source = batch->query[lane] ? lane : first;
    rays.org_x[lane] = batch->origin[0];
    rays.org_y[lane] = batch->origin[1];
    rays.org_z[lane] = batch->origin[2];
    rays.dir_x[lane] = batch->dir[0][source];
    rays.dir_y[lane] = batch->dir[1][source];
    rays.dir_z[lane] = batch->dir[2][source];
    rays.tnear[lane] = 0.0f;
    rays.tfar[lane] = batch->tfar;
    rays.time[lane] = 0.0f;
    rays.mask[lane] = 0xFFFFFFFFu;
    rays.id[lane] = static_cast<unsigned>(lane);
    rays.flags[lane] = 0;
  }
  rtcOccluded16(valid, scene, &context, &rays);
  // Embree sets tfar to -inf on the occluded rays.
  for (int lane = 0; lane < 16; ++lane)
    if (batch->query[lane]) batch->occluded[lane] = !(rays.tfar[lane] >= 0.0f);
}

}  // namespace

void RayScene::Intersect(RayBatch* batch) const {
  IntersectPacket(impl_->scene, impl_->is_target, impl_->target_mesh, nullptr, batch);
}

void RayScene::Occluded(OcclusionBatch* batch) const { OccludedPacket(impl_->scene, batch); }

RayHit RayScene::IntersectHit(const float origin[3], const float dir[3], float tfar) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit ray{};
  ray.ray.org_x = origin[0];
  ray.ray.org_y = origin[1];
  ray.ray.org_z = origin[2];
  ray.ray.dir_x = dir[0];
  ray.ray.dir_y = dir[1];
  ray.ray.dir_z = dir[2];
  ray.ray.tnear = 0.0f;
  ray.ray.tfar = tfar;
  ray.ray.mask = 0xFFFFFFFFu;  // Debian's Embree has ray masks on (debian-deps.md)
  ray.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  ray.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(impl_->scene, &context, &ray);
  RayHit hit;
  if (ray.hit.geomID == RTC_INVALID_GEOMETRY_ID) {
    hit.t = std::numeric_limits<float>::infinity();
    return hit;
  }
  hit.t = ray.ray.tfar;
  hit.object = impl_->object[ray.hit.geomID];
  hit.triangle = ray.hit.primID;
  hit.normal[0] = ray.hit.Ng_x;
  hit.normal[1] = ray.hit.Ng_y;
  hit.normal[2] = ray.hit.Ng_z;
  hit.is_target = impl_->is_target[ray.hit.geomID] != 0;
  if (hit.is_target) {
    const Vec3 point =
        TargetPoint(*impl_->target_mesh[ray.hit.geomID], ray.hit.primID, ray.hit.u, ray.hit.v);
    for (int a = 0; a < 3; ++a) hit.point[a] = point[a];
  }
  return hit;
}

// ----- bodies placed per view (issue 45) ------------------------------------------------------

struct RayBodies::Impl {
  RTCDevice device = nullptr;         // retained: the RayScene's
  std::vector<RTCScene> scenes;       // one per mesh; null for an empty one
  ~Impl() {
    for (RTCScene scene : scenes)
      if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

RayBodies::RayBodies(const RayScene& scene, std::span<const TriangleMesh> meshes)
    : impl_(std::make_unique<Impl>()) {
  impl_->device = scene.impl_->device;
  rtcRetainDevice(impl_->device);
  for (const TriangleMesh& mesh : meshes) {
    if (mesh.triangles.empty()) {
      impl_->scenes.push_back(nullptr);
      continue;
    }
    RTCScene body = rtcNewScene(impl_->device);
    impl_->scenes.push_back(body);  // released by Impl whatever follows
    rtcSetSceneFlags(body, RTC_SCENE_FLAG_ROBUST);
    RTCGeometry geometry = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float),
        mesh.vertices.size()));
    auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned),
        mesh.triangles.size()));
    VANTAGE_CHECK(vertices != nullptr && indices != nullptr);
    for (size_t i = 0; i < mesh.vertices.size(); ++i)
      for (int a = 0; a < 3; ++a) vertices[3 * i + a] = static_cast<float>(mesh.vertices[i][a]);
    for (size_t i = 0; i < mesh.triangles.size(); ++i)
      for (int a = 0; a < 3; ++a) indices[3 * i + a] = mesh.triangles[i][a];
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(body, geometry);
    rtcReleaseGeometry(geometry);
    rtcCommitScene(body);
  }
}

RayBodies::~RayBodies() = default;
size_t RayBodies::size() const { return impl_->scenes.size(); }

struct PlacedRayScene::Impl {
  const RayScene::Impl* scene = nullptr;  // the static scene's tables
  RTCScene top = nullptr;
  std::vector<Mat3> body_to_world;        // by instance id; [kSceneInstance] unused
  ~Impl() {
    if (top) rtcReleaseScene(top);
  }
};

namespace {

// An instance of `scene` at `world_from_local`, attached to `top` with the next id.
unsigned AttachInstance(RTCDevice device, RTCScene top, RTCScene scene, const Pose& world_from_local) {
  const Mat3 rotation = world_from_local.rotation.toRotationMatrix();
  float transform[12];  // RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR: the rotation's columns, then the offset
  for (int column = 0; column < 3; ++column)
    for (int row = 0; row < 3; ++row) transform[3 * column + row] = static_cast<float>(rotation(row, column));
  for (int row = 0; row < 3; ++row) transform[9 + row] = static_cast<float>(world_from_local.position[row]);
  for (const float value : transform)
    if (!std::isfinite(value)) throw InternalError("a body's pose is not finite");
  RTCGeometry instance = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_INSTANCE);
  rtcSetGeometryInstancedScene(instance, scene);
  rtcSetGeometryTransform(instance, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, transform);
  rtcCommitGeometry(instance);
  const unsigned id = rtcAttachGeometry(top, instance);
  rtcReleaseGeometry(instance);
  return id;
}

}  // namespace

PlacedRayScene::PlacedRayScene(const RayScene& scene, const RayBodies& bodies,
                               std::span<const Pose> world_from_body,
                               std::span<const uint8_t> placed)
    : impl_(std::make_unique<Impl>()) {
  VANTAGE_CHECK(world_from_body.size() == bodies.size());
  VANTAGE_CHECK(placed.empty() || placed.size() == bodies.size());
  impl_->scene = scene.impl_.get();
  RTCDevice device = scene.impl_->device;
  VANTAGE_CHECK(bodies.impl_->device == device);
  impl_->top = rtcNewScene(device);
  rtcSetSceneFlags(impl_->top, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(impl_->top, RTC_BUILD_QUALITY_LOW);  // a handful of boxes
  VANTAGE_CHECK(AttachInstance(device, impl_->top, scene.impl_->scene, Pose{}) == kSceneInstance);
  impl_->body_to_world.resize(1);
  for (size_t b = 0; b < bodies.size(); ++b) {
    RTCScene body = bodies.impl_->scenes[b];
    if (!body || (!placed.empty() && placed[b] == 0)) continue;
    const unsigned id = AttachInstance(device, impl_->top, body, world_from_body[b]);
    VANTAGE_CHECK(id == impl_->body_to_world.size());
    impl_->body_to_world.push_back(world_from_body[b].rotation.toRotationMatrix());
  }
  rtcCommitScene(impl_->top);
}

PlacedRayScene::~PlacedRayScene() = default;
PlacedRayScene::PlacedRayScene(PlacedRayScene&&) noexcept = default;
PlacedRayScene& PlacedRayScene::operator=(PlacedRayScene&&) noexcept = default;

void PlacedRayScene::Intersect(RayBatch* batch) const {
  IntersectPacket(impl_->top, impl_->scene->is_target, impl_->scene->target_mesh,
                  &impl_->body_to_world, batch);
}

void PlacedRayScene::Occluded(OcclusionBatch* batch) const { OccludedPacket(impl_->top, batch); }

}  // namespace vantage
