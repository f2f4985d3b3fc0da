#include "observe/arm_occlusion.hpp"

#include <embree3/rtcore.h>

#include <cmath>
#include <limits>
#include <vector>

#include "vantage/error.hpp"

namespace vantage::detail {

struct ArmOcclusion::Impl {
  RTCDevice device = nullptr;
  /// Per ArmBody, one committed scene per link (null for a link without triangles).
  std::map<const ArmBody*, std::vector<RTCScene>> links;
  ~Impl() {
    for (auto& [body, scenes] : links)
      for (RTCScene scene : scenes)
        if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

ArmOcclusion::ArmOcclusion(std::span<const Candidate> candidates)
    : impl_(std::make_unique<Impl>()) {
  for (const Candidate& candidate : candidates) {
    if (!candidate.arm) continue;
    const ArmBody* body = candidate.arm->body.get();
    VANTAGE_CHECK(body != nullptr);
    if (impl_->links.count(body)) continue;
    if (!impl_->device) {
      impl_->device = rtcNewDevice(nullptr);
      if (!impl_->device) throw InternalError("cannot create the Embree device");
    }
    std::vector<RTCScene>& scenes = impl_->links[body];
    for (const TriangleMesh& mesh : body->link_meshes) {
      if (mesh.IsEmpty()) {
        scenes.push_back(nullptr);
        continue;
      }
      RTCScene scene = rtcNewScene(impl_->device);
      rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST);
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
      rtcAttachGeometry(scene, geometry);
      rtcReleaseGeometry(geometry);
      rtcCommitScene(scene);
      scenes.push_back(scene);
    }
  }
}

ArmOcclusion::~ArmOcclusion() = default;

void ArmOcclusion::Clip(const ArmPose& arm, RayBatch* batch) const {
  const auto found = impl_->links.find(arm.body.get());
  VANTAGE_CHECK(found != impl_->links.end());
  const std::vector<RTCScene>& scenes = found->second;
  VANTAGE_CHECK(scenes.size() == arm.world_from_link.size());
  const Vec3 origin(batch->origin[0], batch->origin[1], batch->origin[2]);
  for (size_t l = 0; l < scenes.size(); ++l) {
    if (!scenes[l]) continue;
    // The packet in the link's frame: a rigid motion keeps the ray parameter t.
    const Pose link_from_world = arm.world_from_link[l].Inverse();
    const Mat3 rotation = link_from_world.rotation.toRotationMatrix();
    const Vec3 local_origin = link_from_world * origin;
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    alignas(64) int valid[16];
    alignas(64) RTCRayHit16 rays;
    for (int lane = 0; lane < 16; ++lane) {
      const int source = lane < batch->active ? lane : 0;  // idle lanes repeat lane 0 (RayScene)
      valid[lane] = lane < batch->active ? -1 : 0;
      const Vec3 d = rotation * Vec3(batch->dir[0][source], batch->dir[1][source],
                                     batch->dir[2][source]);
      rays.ray.org_x[lane] = static_cast<float>(local_origin.x());
      rays.ray.org_y[lane] = static_cast<float>(local_origin.y());
      rays.ray.org_z[lane] = static_cast<float>(local_origin.z());
      rays.ray.dir_x[lane] = static_cast<float>(d.x());
      rays.ray.dir_y[lane] = static_cast<float>(d.y());
      rays.ray.dir_z[lane] = static_cast<float>(d.z());
      rays.ray.tnear[lane] = 0.0f;
      // Only a link before the scene's hit matters.
      const float scene_t = lane < batch->active ? batch->t[source] : batch->tfar;
      rays.ray.tfar[lane] = std::isfinite(scene_t) ? scene_t : batch->tfar;
      rays.ray.time[lane] = 0.0f;
      rays.ray.mask[lane] = 0xFFFFFFFFu;
      rays.ray.id[lane] = static_cast<unsigned>(lane);
      rays.ray.flags[lane] = 0;
      rays.hit.geomID[lane] = RTC_INVALID_GEOMETRY_ID;
      rays.hit.instID[0][lane] = RTC_INVALID_GEOMETRY_ID;
    }
    rtcIntersect16(valid, scenes[l], &context, &rays);
    const Mat3 to_world = arm.world_from_link[l].rotation.toRotationMatrix();
    for (int lane = 0; lane < batch->active; ++lane) {
      if (rays.hit.geomID[lane] == RTC_INVALID_GEOMETRY_ID) continue;
      if (!(rays.ray.tfar[lane] < batch->t[lane])) continue;
      batch->t[lane] = rays.ray.tfar[lane];
      batch->is_target[lane] = false;  // the carrying robot's links are occluders
      const Vec3 n = to_world * Vec3(rays.hit.Ng_x[lane], rays.hit.Ng_y[lane], rays.hit.Ng_z[lane]);
      for (int a = 0; a < 3; ++a) batch->normal[a][lane] = static_cast<float>(n[a]);
    }
  }
}

}  // namespace vantage::detail
