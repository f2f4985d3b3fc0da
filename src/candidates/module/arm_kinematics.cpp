// The kinematics of a camera-carrying arm (issue 45): the chain from the robot's root to the
// camera's link as an Orocos KDL chain (its forward kinematics and Jacobian), and inverse
// kinematics by damped least squares on that Jacobian. KDL's own position solvers match the
// whole 6-D pose only; the camera's views need position + optical axis (roll free) too, so the
// task error and its rows are built here.
#include <kdl/chain.hpp>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainjnttojacsolver.hpp>
#include <kdl/frames.hpp>
#include <kdl/jacobian.hpp>
#include <kdl/jntarray.hpp>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "vantage/arm.hpp"
#include "vantage/error.hpp"
#include "vantage/rng.hpp"

namespace vantage {
namespace {

constexpr int kIkIterations = 150;
constexpr double kDamping = 0.05;    ///< λ of damped least squares [m or rad]
constexpr double kMaxStep = 0.3;     ///< the largest joint step of one iteration [rad or m]

KDL::Frame ToKdl(const Pose& pose) {
  const Quat& q = pose.rotation;
  return KDL::Frame(KDL::Rotation::Quaternion(q.x(), q.y(), q.z(), q.w()),
                    KDL::Vector(pose.position.x(), pose.position.y(), pose.position.z()));
}

Pose FromKdl(const KDL::Frame& frame) {
  double x, y, z, w;
  frame.M.GetQuaternion(x, y, z, w);
  return Pose{Vec3(frame.p.x(), frame.p.y(), frame.p.z()), Quat(w, x, y, z).normalized()};
}

/// The rotation vector (axis · angle) taking `from` to `to`: R_to · R_from⁻¹ as angle-axis.
Vec3 RotationError(const Quat& from, const Quat& to) {
  const Eigen::AngleAxisd delta((to * from.conjugate()).normalized());
  double angle = delta.angle();
  Vec3 axis = delta.axis();
  if (angle > std::numbers::pi) angle -= 2 * std::numbers::pi;
  return axis * angle;
}

}  // namespace

struct ArmKinematics::Impl {
  /// Its own copy: the tour uses the kinematics after the scene's Problem is gone.
  PlacedRobot own;
  const PlacedRobot* robot = nullptr;
  std::string tip;
  KDL::Chain chain;
  /// Per KDL joint of the chain, its index in joint_names_.
  std::vector<size_t> chain_joint;
  /// Per KDL joint, whether IK moves it (in `moved`).
  std::vector<bool> chain_moved;
};

ArmKinematics::ArmKinematics(const PlacedRobot& robot, const std::string& tip_link,
                             const std::vector<std::string>& moved)
    : impl_(new Impl(), [](Impl* impl) { delete impl; }) {
  impl_->own = robot;
  impl_->own.visual_meshes.clear();
  impl_->own.collision_shapes.clear();
  impl_->robot = &impl_->own;
  const RobotModel& model = impl_->own.model;
  impl_->tip = tip_link;
  for (const RobotJoint& joint : model.joints) {
    if (!joint.IsSettable()) continue;
    joint_names_.push_back(joint.name);
    limits_.push_back(joint.limits.value_or(std::make_pair(-std::numeric_limits<double>::infinity(),
                                                           std::numeric_limits<double>::infinity())));
  }
  const auto index_of = [&](const std::string& name) {
    const auto it = std::find(joint_names_.begin(), joint_names_.end(), name);
    return it == joint_names_.end() ? joint_names_.size()
                                    : static_cast<size_t>(it - joint_names_.begin());
  };
  for (const std::string& name : moved) {
    const size_t i = index_of(name);
    VANTAGE_CHECK(i < joint_names_.size());
    moved_.push_back(i);
  }
  std::sort(moved_.begin(), moved_.end());
  // The joints from the root to the tip, root first.
  VANTAGE_CHECK(std::find(model.links.begin(), model.links.end(), tip_link) != model.links.end());
  std::vector<const RobotJoint*> path;
  for (std::string at = tip_link; at != model.root_link;) {
    const auto joint = std::find_if(model.joints.begin(), model.joints.end(),
                                    [&](const RobotJoint& j) { return j.child_link == at; });
    VANTAGE_CHECK(joint != model.joints.end());
    path.insert(path.begin(), &*joint);
    at = joint->parent_link;
  }
  const std::vector<double> rest = Rest();
  for (const RobotJoint* joint : path) {
    // The joint's origin, then its motion about (or along) the axis in the joint frame.
    impl_->chain.addSegment(KDL::Segment(joint->name + "/origin", KDL::Joint(KDL::Joint::None),
                                         ToKdl(joint->parent_from_joint)));
    const KDL::Vector axis(joint->axis.x(), joint->axis.y(), joint->axis.z());
    const bool prismatic = joint->type == RobotJoint::Type::kPrismatic;
    if (joint->IsSettable()) {
      impl_->chain.addSegment(KDL::Segment(
          joint->name,
          KDL::Joint(joint->name, KDL::Vector::Zero(), axis,
                     prismatic ? KDL::Joint::TransAxis : KDL::Joint::RotAxis),
          KDL::Frame::Identity()));
      const size_t i = index_of(joint->name);
      impl_->chain_joint.push_back(i);
      impl_->chain_moved.push_back(std::find(moved_.begin(), moved_.end(), i) != moved_.end());
    } else if (!joint->mimic.empty() && joint->type != RobotJoint::Type::kFixed) {
      // A mimic joint on the chain: fixed at its rest position for the Jacobian; every answer
      // is checked with the exact forward kinematics (LinkPoses), which makes it follow.
      const double q = joint->mimic_multiplier * rest[index_of(joint->mimic)] + joint->mimic_offset;
      const KDL::Joint motion(joint->name, KDL::Vector::Zero(), axis,
                              prismatic ? KDL::Joint::TransAxis : KDL::Joint::RotAxis);
      impl_->chain.addSegment(
          KDL::Segment(joint->name + "/mimic", KDL::Joint(KDL::Joint::None), motion.pose(q)));
    }
  }
}

ArmKinematics::~ArmKinematics() = default;
ArmKinematics::ArmKinematics(ArmKinematics&&) noexcept = default;
ArmKinematics& ArmKinematics::operator=(ArmKinematics&&) noexcept = default;

std::vector<double> ArmKinematics::Rest() const {
  std::vector<double> rest(joint_names_.size(), 0.0);
  for (size_t i = 0; i < joint_names_.size(); ++i) {
    const auto it = impl_->robot->joints.find(joint_names_[i]);
    if (it != impl_->robot->joints.end()) rest[i] = it->second;
  }
  return rest;
}

std::map<std::string, Pose> ArmKinematics::LinkPosesAt(
    const std::vector<double>& configuration) const {
  VANTAGE_CHECK(configuration.size() == joint_names_.size());
  JointPositions positions;
  for (size_t i = 0; i < joint_names_.size(); ++i) positions[joint_names_[i]] = configuration[i];
  return LinkPoses(impl_->robot->model, impl_->robot->world_from_base, positions);
}

Pose ArmKinematics::TipPose(const std::vector<double>& configuration) const {
  KDL::JntArray q(impl_->chain.getNrOfJoints());
  for (size_t k = 0; k < impl_->chain_joint.size(); ++k)
    q(static_cast<unsigned>(k)) = configuration[impl_->chain_joint[k]];
  // A copy per call: KDL::Joint caches its last pose in mutable members, so one chain shared by
  // threads races (views differed from run to run by one in a thousand).
  const KDL::Chain chain = impl_->chain;
  KDL::ChainFkSolverPos_recursive fk(chain);
  KDL::Frame base_from_tip;
  VANTAGE_CHECK(fk.JntToCart(q, base_from_tip) >= 0);
  return impl_->robot->world_from_base * FromKdl(base_from_tip);
}

std::optional<std::vector<double>> ArmKinematics::SolveIk(
    const Pose& world_from_camera, const Pose& tip_from_camera, Match match,
    double position_tolerance, double angle_tolerance, const std::vector<double>& start,
    int restarts, uint64_t seed, uint64_t stream) const {
  VANTAGE_CHECK(start.size() == joint_names_.size());
  const KDL::Chain chain = impl_->chain;  // a copy per call: KDL joints cache (see TipPose)
  const unsigned n = chain.getNrOfJoints();
  KDL::ChainFkSolverPos_recursive fk(chain);
  KDL::ChainJntToJacSolver jacobian_solver(chain);
  KDL::Jacobian jacobian(n);
  const Mat3 world_from_base = impl_->robot->world_from_base.rotation.toRotationMatrix();
  const Vec3 target_axis = world_from_camera.rotation * Vec3::UnitX();

  // The task error at a configuration: position (3) and orientation (3; for kDirection the turn
  // of the optical axis onto the target's, for kPosition nothing).
  const auto error_at = [&](const Pose& camera, Eigen::Matrix<double, 6, 1>* error) {
    error->head<3>() = world_from_camera.position - camera.position;
    Vec3 turn = Vec3::Zero();
    if (match == Match::kPose) {
      turn = RotationError(camera.rotation, world_from_camera.rotation);
    } else if (match == Match::kDirection) {
      const Vec3 axis = camera.rotation * Vec3::UnitX();
      const Vec3 cross = axis.cross(target_axis);
      const double angle = std::atan2(cross.norm(), axis.dot(target_axis));
      turn = cross.norm() > 1e-15 ? Vec3(cross.normalized() * angle)
                                  : (angle > 1 ? Vec3(axis.unitOrthogonal() * angle) : Vec3::Zero());
    }
    error->tail<3>() = turn;
    return std::pair(error->head<3>().norm(), turn.norm());
  };
  const auto within_limits = [&](const std::vector<double>& q) {
    for (size_t i = 0; i < q.size(); ++i)
      if (q[i] < limits_[i].first || q[i] > limits_[i].second) return false;
    return true;
  };
  // The answer is judged with the exact forward kinematics of the whole robot.
  const auto accepted = [&](const std::vector<double>& q) {
    if (!within_limits(q)) return false;
    const Pose camera = LinkPosesAt(q).at(impl_->tip) * tip_from_camera;
    Eigen::Matrix<double, 6, 1> error;
    const auto [position, angle] = error_at(camera, &error);
    return position <= position_tolerance && angle <= angle_tolerance;
  };

  for (int attempt = 0; attempt < restarts; ++attempt) {
    std::vector<double> q = start;
    if (attempt > 0) {
      Rng rng(seed, Stream::kArmIk, stream, static_cast<uint64_t>(attempt));
      for (size_t i : moved_) {
        const auto [lo, hi] = limits_[i];
        q[i] = std::isfinite(lo) && std::isfinite(hi) ? rng.Uniform(lo, hi)
                                                      : rng.Uniform(-std::numbers::pi,
                                                                    std::numbers::pi);
      }
    }
    for (int iteration = 0; iteration < kIkIterations; ++iteration) {
      KDL::JntArray kq(n);
      for (unsigned k = 0; k < n; ++k) kq(k) = q[impl_->chain_joint[k]];
      KDL::Frame base_from_tip;
      fk.JntToCart(kq, base_from_tip);
      const Pose world_from_tip = impl_->robot->world_from_base * FromKdl(base_from_tip);
      const Pose camera = world_from_tip * tip_from_camera;
      Eigen::Matrix<double, 6, 1> error;
      const auto [position, angle] = error_at(camera, &error);
      if (position <= position_tolerance * 0.5 && angle <= angle_tolerance * 0.5) break;
      jacobian_solver.JntToJac(kq, jacobian);
      // Columns of the moved joints, in the world, referred to the camera's centre.
      Eigen::MatrixXd task(6, n);
      const Vec3 lever = camera.position - world_from_tip.position;
      for (unsigned k = 0; k < n; ++k) {
        Vec3 v(jacobian(0, k), jacobian(1, k), jacobian(2, k));
        Vec3 w(jacobian(3, k), jacobian(4, k), jacobian(5, k));
        v = world_from_base * v;
        w = world_from_base * w;
        if (!impl_->chain_moved[k]) v = w = Vec3::Zero();
        task.block<3, 1>(0, k) = v + w.cross(lever);
        task.block<3, 1>(3, k) = w;
      }
      if (match == Match::kDirection) {
        // Only the turn that moves the optical axis counts: the roll about it is free.
        const Vec3 axis = camera.rotation * Vec3::UnitX();
        const Mat3 across = Mat3::Identity() - axis * axis.transpose();
        task.bottomRows<3>() = across * task.bottomRows<3>();
      } else if (match == Match::kPosition) {
        task.bottomRows<3>().setZero();
      }
      const Eigen::Matrix<double, 6, 6> damped =
          task * task.transpose() + kDamping * kDamping * Eigen::Matrix<double, 6, 6>::Identity();
      Eigen::VectorXd step = task.transpose() * damped.ldlt().solve(error);
      const double largest = step.cwiseAbs().maxCoeff();
      if (largest > kMaxStep) step *= kMaxStep / largest;
      for (unsigned k = 0; k < n; ++k) {
        const size_t i = impl_->chain_joint[k];
        q[i] = std::clamp(q[i] + step(k), limits_[i].first, limits_[i].second);
      }
    }
    if (!accepted(q)) continue;
    // A turned joint reaches the same pose 2π further on: of the equivalent angles within its
    // limits, take the one nearest the start's (home), so that restarts drawn far away do not
    // leave views that the arm reaches only by long detours.
    for (size_t i : moved_) {
      const RobotJoint* joint = impl_->robot->model.FindJoint(joint_names_[i]);
      if (joint->type != RobotJoint::Type::kRevolute && joint->type != RobotJoint::Type::kContinuous)
        continue;
      // A joint that mimics it with another ratio would not come back to its pose.
      const auto& joints = impl_->robot->model.joints;
      if (std::any_of(joints.begin(), joints.end(),
                      [&](const RobotJoint& j) { return j.mimic == joint->name; }))
        continue;
      const double turn = 2 * std::numbers::pi;
      const double nearest = q[i] + turn * std::round((start[i] - q[i]) / turn);
      for (const double candidate : {nearest, nearest - turn, nearest + turn}) {
        if (candidate < limits_[i].first || candidate > limits_[i].second) continue;
        if (std::abs(candidate - start[i]) < std::abs(q[i] - start[i])) q[i] = candidate;
      }
    }
    return q;
  }
  return std::nullopt;
}

}  // namespace vantage
