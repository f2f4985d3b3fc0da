#pragma once
/// Candidate sensors: populations deployed in regions (GAZEBO.md semantics), explicit poses,
/// the look-at orientation and random roll of the paper's 4-DoF reduction. Where sensors may go
/// (Population, ExplicitSensor) is declared by the scene (population.hpp); this stage places them.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "vantage/population.hpp"
#include "vantage/scene.hpp"
#include "vantage/sensors.hpp"
#include "vantage/types.hpp"

namespace vantage {

/// The links of a robot that carries cameras (issue 45): their visual meshes in the link frames,
/// shared by every view of the robot, so that observe builds each link's BVH once.
struct ArmBody {
  std::string robot;
  std::vector<std::string> links;          ///< links with visuals
  std::vector<TriangleMesh> link_meshes;   ///< one per link, link frame
  std::vector<std::string> joint_names;    ///< the robot's settable joints, tree order
};

/// A camera on an arm as one view stands (population kind `arm` or `reach:`): the arm's joints
/// and where its links are, which occlude the camera in this view.
struct ArmPose {
  std::shared_ptr<const ArmBody> body;
  std::vector<double> joints;           ///< one per body->joint_names [rad or m]
  std::vector<Pose> world_from_link;    ///< one per body->links
};

/// One candidate: a sensor type at a world pose of its camera body frame (x forward).
struct Candidate {
  std::string name;
  std::string type_id;  ///< catalog id when the intrinsics match one, else the type's own name
  SensorType sensor;
  Pose world_from_body;
  std::string population;  ///< population name, or "" for explicit sensors
  /// A camera on a robot arm: the arm's configuration in this view; null for a fixed camera.
  std::shared_ptr<const ArmPose> arm;
};

/// Throws InputError "WHERE: ..." unless `candidate` can become rays (issue 15): a finite pose
/// with its position within ±kMaxWorldCoordinate, and a valid type (SensorType::Validate: the
/// range and the pixel rays). The pipeline runs it on every candidate before any ray (Prepare,
/// Evaluate, SelectFromFile), and Observe on what it is given, before culling, so that culling
/// cannot hide a candidate that would break the ray caster.
void CheckCandidate(const Candidate& candidate, const std::string& where);

/// Rotation whose columns are (front, left, up') looking from `eye` to `target` with up = +Z;
/// when front is parallel to Z, left = +Y (GAZEBO.md). Throws InputError when eye == target.
Quat LookAt(const Vec3& eye, const Vec3& target);

/// Positions of a population's clones in the world, in clone order (GAZEBO.md, exactly: the
/// box shift before rotation, the uniform lattice + k-means, cylinder radius uniform in ρ,
/// grid centring, linear offsets). Random draws come from streams keyed by (seed, population
/// index, clone index). Throws InputError for unsupported combinations.
std::vector<Vec3> PopulationPositions(const Population& population, uint64_t seed,
                                      uint32_t population_index);

struct DeployOptions {
  Vec3 observation_point = Vec3::Zero();
  bool random_roll = false;  ///< roll = U(0, 4π) after the look-at (the plugin's quirk)
  uint64_t seed = 1;
};

/// Every candidate of the populations (in order, clone names "<population>_<i>") followed by the
/// explicit sensors. `types` resolves sensor_type keys; the candidate's type_id is the catalog
/// id when the intrinsics match one.
std::vector<Candidate> DeployCandidates(const std::vector<Population>& populations,
                                        const std::vector<ExplicitSensor>& sensors,
                                        const std::vector<SensorType>& types,
                                        const DeployOptions& options);

}  // namespace vantage
