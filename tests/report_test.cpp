// Outputs: the visibility file round trip and its corruption checks, report.json against the
// shared JSON Schema (validated by a small independent validator below), PLY and constellation.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <fstream>
#include <nlohmann/json.hpp>

#include "test_util.hpp"
#include "vantage/error.hpp"
#include "vantage/pipeline.hpp"
#include "vantage/report.hpp"

namespace vantage {
namespace {

using nlohmann::json;

VisibilityFile SmallData() {
  VisibilityFile data;
  data.scene = "scene.yaml";
  data.seed = 7;
  data.selection.n = 2;
  data.reference.cell_size = 0.005;
  for (int64_t i = 0; i < 10; ++i) data.reference.keys.push_back(PackVoxel({i, -i, 2 * i}));
  std::sort(data.reference.keys.begin(), data.reference.keys.end());
  for (int k = 0; k < 3; ++k) {
    Candidate c;
    c.name = "cam" + std::to_string(k);
    c.type_id = "intel_realsense_sr300";
    c.sensor = *FindCatalogType("intel_realsense_sr300");
    c.world_from_body = Pose{Vec3(0.1 * k, 0.2, 0.5), Quat(Eigen::AngleAxisd(0.3 * k, Vec3::UnitZ()))};
    c.population = "pop";
    data.candidates.push_back(c);
    Observation o;
    for (uint32_t r = static_cast<uint32_t>(k); r < 10; r += 3) o.reference_indices.push_back(r);
    o.outside_keys = {PackVoxel({100 + k, 0, 0})};
    o.rays_traced = 1000u * static_cast<uint64_t>(k);
    data.observations.push_back(o);
  }
  return data;
}

// Files hold quaternions as [w, x, y, z]: checked against rotations of known effect.
TEST(Quaternion, WxyzOrderIsWFirstAndUnitLength) {
  // A turn of 0.6 rad about z: w = cos 0.3, z = sin 0.3, whatever the length handed in.
  const std::array<double, 4> yaw = WxyzOf(Quat(2 * std::cos(0.3), 0, 0, 2 * std::sin(0.3)));
  EXPECT_NEAR(yaw[0], std::cos(0.3), 1e-15);
  EXPECT_EQ(yaw[1], 0.0);
  EXPECT_EQ(yaw[2], 0.0);
  EXPECT_NEAR(yaw[3], std::sin(0.3), 1e-15);
  // [cos 45°, sin 45°, 0, 0] (any length) is a quarter turn about x: y goes to z.
  const std::array<double, 4> wxyz = {3.0, 3.0, 0.0, 0.0};
  const std::optional<Quat> roll = QuatFromWxyz(wxyz);
  ASSERT_TRUE(roll.has_value());
  EXPECT_NEAR(roll->norm(), 1.0, 1e-15);
  EXPECT_LT((*roll * Vec3::UnitY() - Vec3::UnitZ()).norm(), 1e-12);
  // [0, 0, 0, 1] is a half turn about z: x goes to -x.
  const std::vector<double> half = {0, 0, 0, 1};
  EXPECT_LT((*QuatFromWxyz(half) * Vec3::UnitX() + Vec3::UnitX()).norm(), 1e-12);
  // No direction: nothing.
  EXPECT_FALSE(QuatFromWxyz(std::array<double, 4>{0, 0, 0, 0}).has_value());
  EXPECT_FALSE(QuatFromWxyz(std::array<double, 4>{1e-10, 0, 0, 0}).has_value());
}

TEST(VisibilityFile, RoundTripKeepsEverything) {
  test::TempDir dir;
  const VisibilityFile data = SmallData();
  SaveVisibilityFile(dir.File("m.vis"), data);
  const VisibilityFile back = LoadVisibilityFile(dir.File("m.vis"));
  EXPECT_EQ(back.scene, data.scene);
  EXPECT_EQ(back.seed, data.seed);
  EXPECT_EQ(back.selection.n, data.selection.n);
  EXPECT_EQ(back.reference.keys, data.reference.keys);
  EXPECT_EQ(back.reference.cell_size, data.reference.cell_size);
  ASSERT_EQ(back.candidates.size(), 3u);
  for (size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(back.candidates[i].name, data.candidates[i].name);
    EXPECT_EQ(back.candidates[i].sensor.fx, data.candidates[i].sensor.fx);
    EXPECT_TRUE(back.candidates[i].world_from_body.position.isApprox(data.candidates[i].world_from_body.position));
    EXPECT_EQ(back.observations[i].reference_indices, data.observations[i].reference_indices);
    EXPECT_EQ(back.observations[i].outside_keys, data.observations[i].outside_keys);
    EXPECT_EQ(back.observations[i].rays_traced, data.observations[i].rays_traced);
  }
}

TEST(VisibilityFile, RoundTripKeepsPointCounts) {
  test::TempDir dir;
  VisibilityFile data = SmallData();
  for (size_t i = 0; i < data.observations.size(); ++i) {
    Observation& o = data.observations[i];
    for (size_t j = 0; j < o.reference_indices.size(); ++j)
      o.reference_hits.push_back(static_cast<uint16_t>(i == 2 ? 65535 : 7 * i + j + 1));
  }
  SaveVisibilityFile(dir.File("m.vis"), data);
  const VisibilityFile back = LoadVisibilityFile(dir.File("m.vis"));
  for (size_t i = 0; i < 3; ++i) {
    EXPECT_TRUE(back.observations[i].has_point_counts());
    EXPECT_EQ(back.observations[i].reference_hits, data.observations[i].reference_hits);
  }
  // Counts that do not match the cells are refused.
  data.observations[1].reference_hits.pop_back();
  SaveVisibilityFile(dir.File("bad.vis"), data);
  EXPECT_THROW(LoadVisibilityFile(dir.File("bad.vis")), InputError);
}

TEST(VisibilityFile, RoundTripKeepsMountingRulesAndInterferesFlags) {
  test::TempDir dir;
  VisibilityFile data = SmallData();
  data.candidates[1].sensor.interferes = true;
  data.candidates[2].sensor.interferes = false;
  KeepOutBox robot;
  robot.name = "robot";
  robot.world_from_box =
      Pose{Vec3(0.4, -0.2, 0.9), Quat(Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()))};
  robot.min = Vec3(-0.1, -0.2, -0.3);
  robot.max = Vec3(0.3, 0.2, 0.1);
  robot.file = "/cell/scene.yaml";
  robot.line = 41;
  KeepOutBox tray;
  tray.name = "tray";
  tray.min = Vec3(1, 1, 1);
  tray.max = Vec3(2, 3, 4);
  tray.file = "/cell/scene.yaml";
  tray.line = 45;
  data.mounting.keep_out = {robot, tray};
  data.mounting.min_separation = 0.15;
  data.mounting.min_separation_file = "/cell/scene.yaml";
  data.mounting.min_separation_line = 48;
  data.kept_out = 6;
  SaveVisibilityFile(dir.File("m.vis"), data);
  const VisibilityFile back = LoadVisibilityFile(dir.File("m.vis"));
  EXPECT_FALSE(back.candidates[0].sensor.interferes.has_value());
  EXPECT_EQ(back.candidates[1].sensor.interferes, std::optional<bool>(true));
  EXPECT_EQ(back.candidates[2].sensor.interferes, std::optional<bool>(false));
  ASSERT_EQ(back.mounting.keep_out.size(), 2u);
  for (size_t b = 0; b < 2; ++b) {
    const KeepOutBox& want = data.mounting.keep_out[b];
    const KeepOutBox& got = back.mounting.keep_out[b];
    EXPECT_EQ(got.name, want.name);
    EXPECT_EQ(got.world_from_box.position, want.world_from_box.position);
    EXPECT_EQ(got.world_from_box.rotation.coeffs(), want.world_from_box.rotation.coeffs());
    EXPECT_EQ(got.min, want.min);
    EXPECT_EQ(got.max, want.max);
    EXPECT_EQ(got.file, want.file);
    EXPECT_EQ(got.line, want.line);
  }
  EXPECT_EQ(back.mounting.min_separation, std::optional<double>(0.15));
  EXPECT_EQ(back.mounting.min_separation_file, "/cell/scene.yaml");
  EXPECT_EQ(back.mounting.min_separation_line, 48);
  EXPECT_EQ(back.kept_out, 6u);
  // The shards of one run agree on the rules: they are part of the fingerprint.
  VisibilityFile other = data;
  other.mounting.min_separation = 0.2;
  EXPECT_NE(VisibilityFingerprint(other), VisibilityFingerprint(data));
  // A stored separation no scene may give, or a box whose max does not exceed its min, is a
  // corrupt file.
  data.mounting.min_separation = 0.0;
  SaveVisibilityFile(dir.File("bad_separation.vis"), data);
  EXPECT_THROW(LoadVisibilityFile(dir.File("bad_separation.vis")), InputError);
  data.mounting.min_separation = 0.15;
  data.mounting.keep_out[1].max.y() = 1.0;
  SaveVisibilityFile(dir.File("bad.vis"), data);
  EXPECT_THROW(LoadVisibilityFile(dir.File("bad.vis")), InputError);
}

uint64_t Fnv1a64(const std::string& bytes) {
  uint64_t h = 0xCBF29CE484222325ull;
  for (const unsigned char c : bytes) h = (h ^ c) * 0x100000001B3ull;
  return h;
}

// `body` (a file less its checksum) as format `version`, its FNV-1a 64 checksum recomputed here.
std::string Sealed(std::string body, char version) {
  body[8] = version;
  const uint64_t h = Fnv1a64(body);
  return body + std::string(reinterpret_cast<const char*>(&h), 8);
}

// The bytes of a format-9 file (docs/outputs.md) from a version-10 one saved without how the
// scene was read (SmallData: no scene path, no folders, targets or cell size): less its last 52
// zero bytes (an empty string and four empty lists, u64 0 each, and an absent optional, u32 0 and
// f64 0), with version 9 and the checksum recomputed here (FNV-1a 64).
std::string AsVersion9(const std::string& bytes) {
  std::string body = bytes.substr(0, bytes.size() - 8);
  EXPECT_EQ(body.substr(body.size() - 52), std::string(52, '\0'));
  body.erase(body.size() - 52);
  return Sealed(std::move(body), 9);
}

// A format-10 file keeps how observe read the scene: the absolute path, the folders, targets and
// the cell size override, so that `select` reloads it from any folder. They are not part of the
// fingerprint (shards observed from other folders agree). The same file as format 9 reads without
// them; a stored cell size that no run could have given (CellSizeProblem, as --cell-size) is a
// corrupt file.
TEST(VisibilityFile, Version10KeepsHowTheSceneWasRead) {
  test::TempDir dir;
  VisibilityFile data = SmallData();
  data.scene_path = "/cell/scene.yaml";
  data.load.model_paths = {"/cell/models", "/more/models"};
  data.load.resource_paths = {"/cell/media"};
  data.load.package_paths = {"/ws/src"};
  data.load.targets = {"motor", "bin"};
  data.load.cell_size = 0.004;
  SaveVisibilityFile(dir.File("new.vis"), data);
  const VisibilityFile back = LoadVisibilityFile(dir.File("new.vis"));
  EXPECT_EQ(back.scene_path, "/cell/scene.yaml");
  EXPECT_EQ(back.load.model_paths, data.load.model_paths);
  EXPECT_EQ(back.load.resource_paths, data.load.resource_paths);
  EXPECT_EQ(back.load.package_paths, data.load.package_paths);
  EXPECT_EQ(back.load.targets, data.load.targets);
  EXPECT_EQ(back.load.cell_size, std::optional<double>(0.004));
  EXPECT_EQ(VisibilityFingerprint(back), VisibilityFingerprint(SmallData()));
  SaveVisibilityFile(dir.File("plain.vis"), SmallData());
  test::WriteText(dir.File("v9.vis"), AsVersion9(test::ReadText(dir.File("plain.vis"))));
  const VisibilityFile old = LoadVisibilityFile(dir.File("v9.vis"));
  EXPECT_TRUE(old.scene_path.empty());
  EXPECT_TRUE(old.load.model_paths.empty());
  EXPECT_FALSE(old.load.cell_size.has_value());
  EXPECT_EQ(old.observations[1].reference_indices, SmallData().observations[1].reference_indices);
  for (const double bad : {0.0, -0.005, 1e-300, 1e300, std::numeric_limits<double>::infinity(),
                           std::numeric_limits<double>::quiet_NaN()}) {
    data.load.cell_size = bad;
    SaveVisibilityFile(dir.File("bad.vis"), data);
    EXPECT_THROW(LoadVisibilityFile(dir.File("bad.vis")), InputError) << bad;
  }
}

// Format 11 keeps each camera on an arm's configuration (issue 45), in the layout docs/outputs.md
// gives, built here byte by byte; a file of fixed cameras stays version 10.
TEST(VisibilityFile, Version11KeepsEachArmViewAndFixedCamerasStayVersion10) {
  test::TempDir dir;
  SaveVisibilityFile(dir.File("fixed.vis"), SmallData());
  EXPECT_EQ(test::ReadText(dir.File("fixed.vis"))[8], 10);
  VisibilityFile data = SmallData();
  auto body = std::make_shared<ArmBody>();
  body->robot = "arm";
  body->joint_names = {"shoulder", "elbow"};
  const std::vector<std::vector<double>> joints = {{0.25, -1.5}, {}, {3.0, 0.125}};
  for (size_t i : {0u, 2u}) {
    auto pose = std::make_shared<ArmPose>();
    pose->body = body;
    pose->joints = joints[i];
    data.candidates[i].arm = pose;
  }
  SaveVisibilityFile(dir.File("arm.vis"), data);
  const std::string bytes = test::ReadText(dir.File("arm.vis"));
  EXPECT_EQ(bytes[8], 11);
  // The arm section, last before the checksum: one arm ("arm", its two joints), then per
  // candidate its row (1, 0, 1) and the joints of those on it.
  std::string tail;
  const auto u32 = [&](uint32_t v) { tail.append(reinterpret_cast<const char*>(&v), 4); };
  const auto u64 = [&](uint64_t v) { tail.append(reinterpret_cast<const char*>(&v), 8); };
  const auto f64 = [&](double v) { tail.append(reinterpret_cast<const char*>(&v), 8); };
  const auto str = [&](const std::string& text) {
    u64(text.size());
    tail += text;
  };
  u64(1);
  str("arm");
  u64(2);
  str("shoulder");
  str("elbow");
  u32(1);
  f64(0.25);
  f64(-1.5);
  u32(0);
  u32(1);
  f64(3.0);
  f64(0.125);
  ASSERT_GT(bytes.size(), tail.size() + 8);
  EXPECT_EQ(bytes.substr(bytes.size() - 8 - tail.size(), tail.size()), tail);
  // Everything before it is the version-10 file's (the version byte and checksum aside).
  const std::string fixed = test::ReadText(dir.File("fixed.vis"));
  EXPECT_EQ(bytes.substr(9, bytes.size() - 8 - tail.size() - 9), fixed.substr(9, fixed.size() - 17));

  const VisibilityFile back = LoadVisibilityFile(dir.File("arm.vis"));
  ASSERT_EQ(back.arm_views.size(), 3u);
  EXPECT_EQ(back.arm_views[0], (StoredArmView{"arm", {"shoulder", "elbow"}, {0.25, -1.5}}));
  EXPECT_FALSE(back.arm_views[1].has_value());
  EXPECT_EQ(back.arm_views[2], (StoredArmView{"arm", {"shoulder", "elbow"}, {3.0, 0.125}}));
  for (const Candidate& c : back.candidates) EXPECT_EQ(c.arm, nullptr);  // select rebuilds it
  // Read back and written again (a merge, the Python module's save): the same bytes.
  SaveVisibilityFile(dir.File("again.vis"), back);
  EXPECT_EQ(test::ReadText(dir.File("again.vis")), bytes);
  // The arm views are part of what shards must agree on.
  EXPECT_NE(VisibilityFingerprint(back), VisibilityFingerprint(SmallData()));

  // Corrupt sections (checksum valid): a row beyond the arms, a joint that is no number, an
  // empty arm table, a camera on an arm of no population.
  const std::string head = bytes.substr(0, bytes.size() - 8 - tail.size());
  const auto refused = [&](std::string section, const std::string& words) {
    test::WriteText(dir.File("bad.vis"), Sealed(head + section, 11));
    try {
      LoadVisibilityFile(dir.File("bad.vis"));
      ADD_FAILURE() << "accepted: " << words;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("bad.vis"), std::string::npos) << e.what();
    }
  };
  std::string row_beyond = tail;
  row_beyond[tail.size() - 4 - 16 - 4 - 4 - 16] = 2;  // candidate 0's row
  refused(row_beyond, "its arm 2 is not one of the file's 1");
  std::string nan_joint = tail;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  nan_joint.replace(tail.size() - 8, 8, reinterpret_cast<const char*>(&nan), 8);
  refused(nan_joint, "joint 'elbow' at nan is not a position within ±1e6 [rad or m]");
  std::string far_joint = tail;
  const double far = 1e300;
  far_joint.replace(tail.size() - 8, 8, reinterpret_cast<const char*>(&far), 8);
  refused(far_joint, "joint 'elbow' at 1e+300 is not a position within ±1e6 [rad or m]");
  refused(std::string(8, '\0') + std::string(12, '\0'), "its arm configurations name no arm");
  VisibilityFile orphan = data;
  orphan.candidates[2].population.clear();
  SaveVisibilityFile(dir.File("orphan.vis"), orphan);
  EXPECT_THROW(LoadVisibilityFile(dir.File("orphan.vis")), InputError);
}

// The bytes of a format-8 file (docs/outputs.md) from a version-9 one whose sensors' costs are all
// given: less each candidate's last 4 bytes (u32 0), before the next one's name or, for the last,
// before the mounting (40 zero bytes) and parts (36) sections, with version 8 and the checksum
// recomputed here (FNV-1a 64).
std::string AsVersion8(const std::string& bytes, const std::vector<std::string>& names) {
  std::string body = bytes.substr(0, bytes.size() - 8);
  const std::string zero(4, '\0');
  for (size_t i = names.size(); i >= 1; --i) {
    size_t at = body.size() - 36 - 40 - 4;
    if (i < names.size()) {
      const uint64_t length = names[i].size();
      at = body.find(zero + std::string(reinterpret_cast<const char*>(&length), 8) + names[i]);
    }
    EXPECT_NE(at, std::string::npos);
    EXPECT_EQ(body.substr(at, 4), zero);
    body.erase(at, 4);
  }
  return Sealed(std::move(body), 8);
}

// The bytes of a format-7 file (docs/outputs.md) from a version-8 one whose sensors have no
// incidence term and no flying-pixel threshold: less each candidate's last 20 bytes (f64 0, opt
// absent: all zero), before the next one's name or, for the last, before the mounting (40 zero
// bytes) and parts (36) sections, with version 7 and the checksum recomputed here (FNV-1a 64).
std::string AsVersion7(const std::string& bytes, const std::vector<std::string>& names) {
  std::string body = bytes.substr(0, bytes.size() - 8);
  const std::string zero(20, '\0');
  for (size_t i = names.size(); i >= 1; --i) {
    size_t at = body.size() - 36 - 40 - 20;
    if (i < names.size()) {
      const uint64_t length = names[i].size();
      at = body.find(zero + std::string(reinterpret_cast<const char*>(&length), 8) + names[i]);
    }
    EXPECT_NE(at, std::string::npos);
    EXPECT_EQ(body.substr(at, 20), zero);
    body.erase(at, 20);
  }
  return Sealed(std::move(body), 7);
}

// The bytes of a format-5 file (docs/outputs.md) from a version-7 one whose sensors have no
// second aperture and whose reference has no parts: less the parts section at the end (36 zero
// bytes: no names, empty part and exposure lists, not exposed-only, no left-out counts), each
// observation's ideal flag and empty ideal list (12 zero bytes, last in each candidate), each
// sensor's absent aperture (u32 0 just before the pose) and the physical flag (u32 0 just before
// the cell size), with version 5 and the checksum recomputed here (FNV-1a 64).
std::string AsVersion5(const std::string& bytes, const std::vector<Vec3>& positions,
                       const std::vector<std::string>& names, double cell_size) {
  std::string body = bytes.substr(0, bytes.size() - 8);
  EXPECT_EQ(body.substr(body.size() - 36), std::string(36, '\0'));
  body.erase(body.size() - 36);
  const std::string zero(12, '\0');
  // Each candidate's last 12 bytes: before the next one's name (u64 length + text), or before
  // the 40-byte mounting section for the last. From the last, so earlier offsets hold.
  for (size_t i = names.size(); i >= 1; --i) {
    size_t at = body.size() - 40 - 12;
    if (i < names.size()) {
      const uint64_t length = names[i].size();
      at = body.find(zero + std::string(reinterpret_cast<const char*>(&length), 8) + names[i]);
    }
    EXPECT_NE(at, std::string::npos);
    EXPECT_EQ(body.substr(at, 12), zero);
    body.erase(at, 12);
  }
  for (const Vec3& p : positions) {
    const size_t at = body.find(std::string(reinterpret_cast<const char*>(p.data()), 24));
    EXPECT_NE(at, std::string::npos);
    EXPECT_EQ(body.substr(at - 4, 4), std::string(4, '\0'));
    body.erase(at - 4, 4);
  }
  const size_t cell = body.find(std::string(reinterpret_cast<const char*>(&cell_size), 8));
  EXPECT_NE(cell, std::string::npos);
  EXPECT_EQ(body.substr(cell - 4, 4), std::string(4, '\0'));
  body.erase(cell - 4, 4);
  return Sealed(std::move(body), 5);
}

// A format-8 file keeps each sensor's noise incidence term and flying-pixel threshold; the same
// file as format 7 reads without them.
TEST(VisibilityFile, Version8KeepsIncidenceTermAndFlyingThreshold) {
  test::TempDir dir;
  VisibilityFile data = SmallData();
  data.candidates[1].sensor.depth_noise = DepthNoise{0.001, 0, 0.002, "test", 0.0001};
  data.candidates[2].sensor.flying_pixel_threshold = 0.05;
  SaveVisibilityFile(dir.File("new.vis"), data);
  const VisibilityFile back = LoadVisibilityFile(dir.File("new.vis"));
  ASSERT_TRUE(back.candidates[1].sensor.depth_noise.has_value());
  EXPECT_EQ(back.candidates[1].sensor.depth_noise->incidence, 0.0001);
  EXPECT_EQ(back.candidates[2].sensor.flying_pixel_threshold, std::optional<double>(0.05));
  EXPECT_FALSE(back.candidates[0].sensor.flying_pixel_threshold.has_value());
  const std::vector<std::string> names = {"cam0", "cam1", "cam2"};
  const VisibilityFile plain = SmallData();
  SaveVisibilityFile(dir.File("plain.vis"), plain);
  test::WriteText(dir.File("v7.vis"), AsVersion7(AsVersion8(AsVersion9(test::ReadText(dir.File("plain.vis"))), names), names));
  const VisibilityFile old = LoadVisibilityFile(dir.File("v7.vis"));
  ASSERT_EQ(old.candidates.size(), 3u);
  for (size_t i = 0; i < 3; ++i) {
    EXPECT_FALSE(old.candidates[i].sensor.flying_pixel_threshold.has_value());
    EXPECT_EQ(old.observations[i].reference_indices, plain.observations[i].reference_indices);
  }
}

// SmallData as older formats could hold it: no second apertures (format 7).
// A format-9 file keeps whether each sensor's unit cost was given (issue 43): a type without a
// price stays without one. The same file as format 8 reads as it always did: every cost given.
TEST(VisibilityFile, Version9KeepsWhetherTheCostIsGiven) {
  test::TempDir dir;
  VisibilityFile data = SmallData();
  data.candidates[1].sensor.cost = 0;
  data.candidates[1].sensor.cost_given = false;
  SaveVisibilityFile(dir.File("new.vis"), data);
  const VisibilityFile back = LoadVisibilityFile(dir.File("new.vis"));
  ASSERT_EQ(back.candidates.size(), 3u);
  EXPECT_TRUE(back.candidates[0].sensor.cost_given);
  EXPECT_FALSE(back.candidates[1].sensor.cost_given);
  EXPECT_TRUE(back.candidates[2].sensor.cost_given);
  // A free type (cost 0 given) and one without a price differ only in the flag: the fingerprint
  // tells them apart.
  VisibilityFile free = data;
  free.candidates[1].sensor.cost_given = true;
  EXPECT_NE(VisibilityFingerprint(back), VisibilityFingerprint(free));
  const std::vector<std::string> names = {"cam0", "cam1", "cam2"};
  const VisibilityFile plain = SmallData();
  SaveVisibilityFile(dir.File("plain.vis"), plain);
  const std::string bytes = AsVersion9(test::ReadText(dir.File("plain.vis")));
  test::WriteText(dir.File("v8.vis"), AsVersion8(bytes, names));
  EXPECT_EQ(test::ReadText(dir.File("v8.vis")).size(), bytes.size() - 3 * 4);
  const VisibilityFile old = LoadVisibilityFile(dir.File("v8.vis"));
  ASSERT_EQ(old.candidates.size(), 3u);
  for (size_t i = 0; i < 3; ++i) {
    EXPECT_TRUE(old.candidates[i].sensor.cost_given);
    EXPECT_EQ(old.candidates[i].sensor.cost, plain.candidates[i].sensor.cost);
    EXPECT_EQ(old.observations[i].reference_indices, plain.observations[i].reference_indices);
  }
  // A flag other than 0 or 1 is a corrupt file, refused with its name.
  std::string bad = bytes.substr(0, bytes.size() - 8);
  const size_t flag = bad.size() - 36 - 40 - 4;  // the last candidate's flag
  ASSERT_EQ(bad.substr(flag, 4), std::string(4, '\0'));
  bad[flag] = 2;
  const uint64_t h = Fnv1a64(bad);
  test::WriteText(dir.File("bad_flag.vis"), bad + std::string(reinterpret_cast<const char*>(&h), 8));
  try {
    LoadVisibilityFile(dir.File("bad_flag.vis"));
    ADD_FAILURE() << "a cost-given flag of 2 was read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("cost-given flag"), std::string::npos) << e.what();
  }
}

VisibilityFile SmallOldData() {
  VisibilityFile data = SmallData();
  for (Candidate& c : data.candidates) c.sensor.second_aperture.reset();
  return data;
}

// The bytes of a format-4 file (docs/outputs.md): a version-5 file without mounting rules, less
// its 40-byte mounting section at the end (no boxes: u64 0; min_separation: opt 0, str "", u32
// 0; kept out: u64 0, all zero bytes) and each sensor's unset interferes flag (u32 0 just before
// the candidate's pose, found by its position's bytes), with version 4 and the checksum
// recomputed here (FNV-1a 64).
std::string AsVersion4(const std::string& bytes, const std::vector<Vec3>& positions) {
  std::string body = bytes.substr(0, bytes.size() - 8);
  EXPECT_EQ(body.substr(body.size() - 40), std::string(40, '\0'));
  body.erase(body.size() - 40);
  for (const Vec3& p : positions) {
    const std::string position(reinterpret_cast<const char*>(p.data()), 3 * sizeof(double));
    const size_t at = body.find(position);
    EXPECT_NE(at, std::string::npos);
    EXPECT_EQ(body.substr(at - 4, 4), std::string(4, '\0'));
    body.erase(at - 4, 4);
  }
  return Sealed(std::move(body), 4);
}

// A format-4 file (written before mounting rules were kept) loads with none and every sensor's
// interferes unset, and select reads it as it did: the same results as the new file.
TEST(VisibilityFile, Version4LoadsWithoutMountingRulesAndSelectsAsBefore) {
  test::TempDir dir;
  const VisibilityFile data = SmallOldData();
  SaveVisibilityFile(dir.File("new.vis"), data);
  std::vector<Vec3> positions;
  for (const Candidate& c : data.candidates) positions.push_back(c.world_from_body.position);
  const std::vector<std::string> names = {"cam0", "cam1", "cam2"};
  test::WriteText(dir.File("v4.vis"),
                  AsVersion4(AsVersion5(AsVersion7(AsVersion8(AsVersion9(test::ReadText(dir.File("new.vis"))), names), names),
                                        positions, names, data.reference.cell_size),
                             positions));
  const VisibilityFile old = LoadVisibilityFile(dir.File("v4.vis"));
  EXPECT_TRUE(old.mounting.empty());
  EXPECT_EQ(old.kept_out, 0u);
  ASSERT_EQ(old.candidates.size(), 3u);
  for (size_t i = 0; i < 3; ++i) {
    EXPECT_FALSE(old.candidates[i].sensor.interferes.has_value());
    EXPECT_EQ(old.observations[i].reference_indices, data.observations[i].reference_indices);
  }
  SelectFileOptions options;
  options.selection.method = Method::kExact;
  options.selection.constraints.interference = true;  // SR300s: structured light, by the technology
  options.visibility_file = dir.File("v4.vis");
  const RunResult from_old = SelectFromFile(options);
  options.visibility_file = dir.File("new.vis");
  const RunResult from_new = SelectFromFile(options);
  ASSERT_EQ(from_old.report.results.size(), from_new.report.results.size());
  EXPECT_EQ(from_old.report.results[0].chosen, from_new.report.results[0].chosen);
  EXPECT_EQ(from_old.report.results[0].coverage, from_new.report.results[0].coverage);
  ASSERT_TRUE(from_old.report.constraints.has_value());
  EXPECT_EQ(from_old.report.constraints->projecting, 3u);
  EXPECT_TRUE(from_old.report.constraints->keep_out_boxes.empty());
}

// The bytes of a format-3 file (no point counts): a version-4 file without counts, less each
// observation's empty count list (8 zero bytes, last in each candidate), with version 3 and the
// checksum recomputed here (FNV-1a 64).
std::string AsVersion3(std::string bytes, const std::vector<std::string>& names) {
  std::string body = bytes.substr(0, bytes.size() - 8);
  const std::string zero(8, '\0');
  // The list ends each candidate: before the next candidate's name (u64 length + text) or the end.
  for (size_t i = 1; i <= names.size(); ++i) {
    size_t at = body.size() - 8;
    if (i < names.size()) {
      uint64_t length = names[i].size();
      std::string next = zero + std::string(reinterpret_cast<const char*>(&length), 8) + names[i];
      at = body.find(next);
    }
    EXPECT_NE(at, std::string::npos);
    EXPECT_EQ(body.substr(at, 8), zero);
    body.erase(at, 8);
  }
  return Sealed(std::move(body), 3);
}

TEST(VisibilityFile, OldVersionLoadsWithoutCountsAndMinPointsRefusesIt) {
  test::TempDir dir;
  const VisibilityFile data = SmallOldData();  // no counts
  SaveVisibilityFile(dir.File("new.vis"), data);
  const std::vector<std::string> names = {"cam0", "cam1", "cam2"};
  std::vector<Vec3> positions;
  for (const Candidate& c : data.candidates) positions.push_back(c.world_from_body.position);
  const std::string v5 = AsVersion5(AsVersion7(AsVersion8(AsVersion9(test::ReadText(dir.File("new.vis"))), names), names),
                                    positions, names, data.reference.cell_size);
  test::WriteText(dir.File("old.vis"), AsVersion3(AsVersion4(v5, positions), names));
  const VisibilityFile old = LoadVisibilityFile(dir.File("old.vis"));
  ASSERT_EQ(old.observations.size(), 3u);
  for (size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(old.observations[i].reference_indices, data.observations[i].reference_indices);
    EXPECT_FALSE(old.observations[i].has_point_counts());
  }
  SelectFileOptions options;
  options.visibility_file = dir.File("old.vis");
  options.selection.method = Method::kGreedy;
  EXPECT_NO_THROW(SelectFromFile(options));  // plain selection still reads it
  options.selection.min_points = 5;
  try {
    SelectFromFile(options);
    ADD_FAILURE() << "--min-points accepted a file without counts";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(dir.File("old.vis")), std::string::npos) << what;
    EXPECT_NE(what.find("--min-points"), std::string::npos) << what;
    EXPECT_NE(what.find("observe"), std::string::npos) << what;
  }
}

TEST(VisibilityFile, CorruptTruncatedOrForeignFilesAreInputErrors) {
  test::TempDir dir;
  SaveVisibilityFile(dir.File("m.vis"), SmallData());
  const std::string good = test::ReadText(dir.File("m.vis"));
  std::string flipped = good;
  flipped[flipped.size() / 2] ^= 0x40;
  test::WriteText(dir.File("flipped.vis"), flipped);
  test::WriteText(dir.File("short.vis"), good.substr(0, good.size() / 3));
  test::WriteText(dir.File("text.vis"), "hello, not a matrix\n");
  std::string other_version = good;
  other_version[8] = 11;  // one past the current format (10)
  test::WriteText(dir.File("version.vis"), other_version);
  for (const char* name : {"flipped.vis", "short.vis", "text.vis", "version.vis", "missing.vis"}) {
    try {
      LoadVisibilityFile(dir.File(name));
      ADD_FAILURE() << name << " was accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(dir.File(name)), std::string::npos) << e.what();
    }
  }
}

// A validator for the subset of JSON Schema that report.schema.json uses.
void Validate(const json& schema, const json& root, const json& value, const std::string& path,
              std::vector<std::string>* errors) {
  if (schema.contains("$ref")) {
    const std::string ref = schema["$ref"];  // "#/$defs/name"
    Validate(root["$defs"][ref.substr(ref.rfind('/') + 1)], root, value, path, errors);
    return;
  }
  const auto fail = [&](const std::string& what) { errors->push_back(path + ": " + what); };
  if (schema.contains("const") && value != schema["const"]) fail("const");
  if (schema.contains("type")) {
    const std::string type = schema["type"];
    const bool ok = (type == "object" && value.is_object()) || (type == "array" && value.is_array()) ||
                    (type == "string" && value.is_string()) || (type == "number" && value.is_number()) ||
                    (type == "integer" && value.is_number_integer()) || (type == "boolean" && value.is_boolean());
    if (!ok) return fail("type " + type);
  }
  if (value.is_number()) {
    const double v = value.get<double>();
    if (schema.contains("minimum") && v < schema["minimum"].get<double>()) fail("minimum");
    if (schema.contains("maximum") && v > schema["maximum"].get<double>()) fail("maximum");
    if (schema.contains("exclusiveMinimum") && v <= schema["exclusiveMinimum"].get<double>()) fail("exclusiveMinimum");
  }
  if (value.is_string() && schema.contains("minLength") && value.get<std::string>().size() < schema["minLength"].get<size_t>())
    fail("minLength");
  if (value.is_array()) {
    if (schema.contains("minItems") && value.size() < schema["minItems"].get<size_t>()) fail("minItems");
    if (schema.contains("maxItems") && value.size() > schema["maxItems"].get<size_t>()) fail("maxItems");
    if (schema.contains("items"))
      for (size_t i = 0; i < value.size(); ++i)
        Validate(schema["items"], root, value[i], path + "[" + std::to_string(i) + "]", errors);
  }
  if (value.is_object()) {
    if (schema.contains("required"))
      for (const auto& key : schema["required"])
        if (!value.contains(key.get<std::string>())) fail("missing " + key.get<std::string>());
    for (const auto& [key, sub] : value.items()) {
      if (schema.contains("properties") && schema["properties"].contains(key)) {
        Validate(schema["properties"][key], root, sub, path + "." + key, errors);
      } else if (schema.contains("additionalProperties") && schema["additionalProperties"].is_object()) {
        Validate(schema["additionalProperties"], root, sub, path + "." + key, errors);
      }
    }
  }
}

std::vector<std::string> SchemaErrors(const json& report) {
  std::ifstream in(std::string(VANTAGE_SHARED_DIR) + "/spec/report.schema.json");
  const json schema = json::parse(in);
  std::vector<std::string> errors;
  Validate(schema, schema, report, "$", &errors);
  return errors;
}

Report SmallReport(const VisibilityFile& data) {
  Report report;
  report.scene = data.scene;
  report.seed = data.seed;
  report.data = &data;
  Selection s;
  s.method = "exact";
  s.n = 2;
  s.chosen = {0, 1};
  s.coverage = 0.7;
  s.paper_coverage = 0.9;
  s.upper_bound = 0.75;
  s.seconds = 0.01;
  report.results = {s};
  report.timings = {0.1, 0.2, 0.3, 0.4, 1.0};
  DeriveReport(&report);
  return report;
}

// report.html's "primary, in order chosen" steps count a cell as the result does: hand-counted
// for a min-points and a k-coverage result over two overlapping sets with pixel counts.
TEST(Report, PrimaryStepsCountCellsAsTheResultDoes) {
  VisibilityFile data = SmallData();
  data.observations[0].reference_indices = {0, 1, 2};
  data.observations[0].reference_hits = {5, 1, 3};
  data.observations[1].reference_indices = {1, 2, 3};
  data.observations[1].reference_hits = {4, 1, 9};
  // A file with min_points counts for every candidate: the ceiling reads the unchosen cam2 too.
  data.observations[2].reference_hits = {1, 1, 1};
  Report report = SmallReport(data);
  // Plain: 3 cells, then cell 3 is new.
  ASSERT_EQ(report.primary_sensors.size(), 2u);
  EXPECT_DOUBLE_EQ(report.primary_sensors[0].cumulative, 0.3);
  EXPECT_DOUBLE_EQ(report.primary_sensors[1].cumulative, 0.4);
  // Five points: cell 0 (5) alone; then cells 1 (1 + 4) and 3 (9), not cell 2 (3 + 1).
  report.results[0].min_points = 5;
  DeriveReport(&report);
  EXPECT_DOUBLE_EQ(report.primary_sensors[0].cumulative, 0.1);
  EXPECT_DOUBLE_EQ(report.primary_sensors[1].cumulative, 0.3);
  // k = 2: no cell after one sensor; cells 1 and 2 after both.
  report.results[0].min_points.reset();
  report.results[0].k = 2;
  DeriveReport(&report);
  EXPECT_DOUBLE_EQ(report.primary_sensors[0].cumulative, 0.0);
  EXPECT_DOUBLE_EQ(report.primary_sensors[1].cumulative, 0.2);
}

TEST(Report, JsonValidatesAgainstTheSharedSchema) {
  const VisibilityFile data = SmallData();
  const json report = json::parse(ReportJson(SmallReport(data)));
  EXPECT_EQ(SchemaErrors(report), std::vector<std::string>{});
  // The validator itself rejects what the schema forbids.
  json broken = report;
  broken["candidates"][0]["coverage"] = 1.5;
  broken.erase("timings");
  EXPECT_EQ(SchemaErrors(broken).size(), 2u);
}

TEST(Report, CandidateValuesAreTheInputs) {
  const VisibilityFile data = SmallData();
  const json report = json::parse(ReportJson(SmallReport(data)));
  const json& c1 = report["candidates"][1];
  EXPECT_EQ(c1["name"], "cam1");
  // Rotation of 0.3 rad about z: q = (cos 0.15, 0, 0, sin 0.15), written w first.
  EXPECT_NEAR(c1["quaternion"][0].get<double>(), std::cos(0.15), 1e-12);
  EXPECT_NEAR(c1["quaternion"][3].get<double>(), std::sin(0.15), 1e-12);
  // cam1 sees reference indices 1, 4, 7: 3 of 10 cells; plus one outside: 4 / 10.
  EXPECT_DOUBLE_EQ(c1["coverage"].get<double>(), 0.3);
  EXPECT_DOUBLE_EQ(c1["paper_coverage"].get<double>(), 0.4);
  EXPECT_EQ(report["reference_voxels"], 10);
  EXPECT_EQ(report["results"][0]["sensors"], json::array({"cam0", "cam1"}));
}

TEST(Report, PlyHeaderAndBinaryBodyMatchTheVoxelCentres) {
  const std::vector<uint64_t> keys = {PackVoxel({0, 0, 0}), PackVoxel({-2, 3, 5})};
  const std::string ply = VoxelPly(keys, 0.5);
  const size_t end = ply.find("end_header\n");
  ASSERT_NE(end, std::string::npos);
  EXPECT_NE(ply.find("format binary_little_endian 1.0"), std::string::npos);
  EXPECT_NE(ply.find("element vertex 2\n"), std::string::npos);
  const char* body = ply.data() + end + 11;
  ASSERT_EQ(ply.size(), end + 11 + 2 * 12);
  float xyz[6];
  std::memcpy(xyz, body, sizeof(xyz));
  // Centres: (0.25, 0.25, 0.25) and (-0.75, 1.75, 2.75).
  EXPECT_FLOAT_EQ(xyz[0], 0.25f);
  EXPECT_FLOAT_EQ(xyz[3], -0.75f);
  EXPECT_FLOAT_EQ(xyz[4], 1.75f);
  EXPECT_FLOAT_EQ(xyz[5], 2.75f);
}

TEST(Report, WriteOutputsReplacesAPreviousRunKeepsTheUsersFilesAndRefusesForeignFolders) {
  test::TempDir dir;
  const VisibilityFile data = SmallData();
  const std::string out = dir.File("out");
  WriteOutputs(out, SmallReport(data), {{"constellation.yaml", "from the first run"}});
  for (const char* name : {"report.json", "candidates.csv", "reference.ply", "observed.ply"})
    EXPECT_TRUE(std::filesystem::exists(out + "/" + name)) << name;
  // The user's notes and a folder of theirs survive a rerun; an output of the first run that the
  // second does not write goes, so that the folder describes one run only.
  test::WriteText(out + "/notes.txt", "mine");
  test::WriteText(out + "/photos/cell.jpg", "jpeg");
  test::WriteText(out + "/report.json", "stale");
  WriteOutputs(out, SmallReport(data));
  EXPECT_EQ(test::ReadText(out + "/notes.txt"), "mine");
  EXPECT_EQ(test::ReadText(out + "/photos/cell.jpg"), "jpeg");
  EXPECT_NE(test::ReadText(out + "/report.json"), "stale");
  EXPECT_FALSE(std::filesystem::exists(out + "/constellation.yaml"));
  // A non-empty folder that vantage did not write is never replaced.
  test::WriteText(dir.File("home/notes.txt"), "precious");
  EXPECT_THROW(WriteOutputs(dir.File("home"), SmallReport(data)), InputError);
  EXPECT_EQ(test::ReadText(dir.File("home/notes.txt")), "precious");
}

TEST(Report, ConstellationRoundTripsThroughReportJson) {
  test::TempDir dir;
  const VisibilityFile data = SmallData();
  test::WriteText(dir.File("report.json"), ReportJson(SmallReport(data)));
  const Constellation c = LoadConstellation(dir.File("report.json"));
  ASSERT_EQ(c.sensors.size(), 2u);  // the result names cam0 and cam1
  EXPECT_EQ(c.sensors[1].name, "cam1");
  EXPECT_TRUE(c.sensors[1].world_from_body.position.isApprox(data.candidates[1].world_from_body.position));
  EXPECT_NEAR(c.sensors[1].sensor.fx, data.candidates[1].sensor.fx, 1e-9);
}

// report.json's constraints.keep_out.regions hold the scene's boxes posed as the scene declares
// them (a rotated robot volume whose corners are not centred on its pose, an axis-aligned tray),
// and the candidates Prepare excluded lie inside them by that geometry, those reported outside.
TEST(Report, KeepOutBoxesInTheConstraintsBlockArePosedAsTheScenesBoxes) {
  const std::string scene = test::DataPath("cli/keep_out_cell.yaml");
  OptimizeOptions options;
  options.scene.path = scene;
  options.selection.method = Method::kGreedy;
  const RunResult run = Optimize(options);
  const json report = json::parse(run.files.at("report.json"));
  EXPECT_EQ(SchemaErrors(report), std::vector<std::string>{});
  const json& keep_out = report["constraints"]["keep_out"];
  EXPECT_EQ(keep_out["boxes"], 2);
  const json& regions = keep_out["regions"];
  ASSERT_EQ(regions.size(), 2u);
  // robot: pose xyz [0.3, 0, 0.45], rpy_deg [15, 10, 40] (R = Rz(yaw) Ry(pitch) Rx(roll)),
  // corners [-0.15, -0.1, -0.2] to [0.15, 0.2, 0.25]: its centre (0, 0.05, 0.025) in its frame.
  const double deg = 3.14159265358979323846 / 180.0;
  const Quat robot_rotation(Eigen::AngleAxisd(40 * deg, Vec3::UnitZ()) *
                            Eigen::AngleAxisd(10 * deg, Vec3::UnitY()) *
                            Eigen::AngleAxisd(15 * deg, Vec3::UnitX()));
  const Vec3 robot_center = Vec3(0.3, 0, 0.45) + robot_rotation * Vec3(0, 0.05, 0.025);
  struct Expected {
    std::string name;
    Vec3 center, size;
    Quat rotation;
  };
  const std::vector<Expected> expected = {
      {"robot", robot_center, Vec3(0.3, 0.3, 0.45), robot_rotation},
      {"cable_tray", Vec3(-0.45, 0.1, 0.6), Vec3(0.2, 1.2, 0.1), Quat::Identity()}};
  struct Box {
    Vec3 center, half;
    Quat rotation;
    bool Holds(const Vec3& p) const {
      return ((rotation.inverse() * (p - center)).cwiseAbs() - half).maxCoeff() <= 1e-12;
    }
  };
  std::vector<Box> boxes;
  for (size_t b = 0; b < 2; ++b) {
    const json& r = regions[b];
    EXPECT_EQ(r["name"], expected[b].name);
    const Vec3 center(r["center"][0].get<double>(), r["center"][1].get<double>(),
                      r["center"][2].get<double>());
    const Vec3 size(r["size"][0].get<double>(), r["size"][1].get<double>(),
                    r["size"][2].get<double>());
    const std::optional<Quat> q = QuatFromWxyz(r["quaternion"].get<std::vector<double>>());
    ASSERT_TRUE(q.has_value());
    EXPECT_LT((center - expected[b].center).norm(), 1e-12) << expected[b].name;
    EXPECT_LT((size - expected[b].size).norm(), 1e-12) << expected[b].name;
    EXPECT_NEAR(std::abs(q->dot(expected[b].rotation)), 1.0, 1e-12) << expected[b].name;
    boxes.push_back({center, 0.5 * size, *q});
  }
  const auto held = [&](const Vec3& p) {
    return std::any_of(boxes.begin(), boxes.end(), [&](const Box& b) { return b.Holds(p); });
  };
  // The excluded candidates (Prepare's, of the same seed) lie in a box by report.json's geometry,
  // each box holding some; every candidate report.json lists lies outside both.
  SceneInput input;
  input.path = scene;
  const PreparedScene prepared = Prepare(input);
  EXPECT_EQ(keep_out["excluded_candidates"], prepared.kept_out.size());
  for (const Candidate& c : prepared.kept_out)
    EXPECT_TRUE(held(c.world_from_body.position)) << c.name;
  for (const Box& box : boxes) {
    EXPECT_TRUE(
        std::any_of(prepared.kept_out.begin(), prepared.kept_out.end(),
                    [&](const Candidate& c) { return box.Holds(c.world_from_body.position); }));
  }
  ASSERT_EQ(report["candidates"].size(), prepared.candidates.size());
  for (const json& c : report["candidates"]) {
    const Vec3 p(c["position"][0].get<double>(), c["position"][1].get<double>(),
                 c["position"][2].get<double>());
    EXPECT_FALSE(held(p)) << c["name"];
  }
  // report.html carries the same boxes for its 3D view.
  const std::string& html = run.files.at("report.html");
  EXPECT_NE(html.find("\"keep_out\":[{\"name\":\"robot\",\"center\":["), std::string::npos);
}

TEST(Report, BadConstellationsNameTheFile) {
  test::TempDir dir;
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"syntax.json", "{\n  \"candidates\": [\n    {\"name\": }\n  ]\n}\n"},
      {"nocand.json", "{\"results\": []}"},
      {"badfov.json", R"({"candidates":[{"name":"a","position":[0,0,0],"quaternion":[1,0,0,0],"width":10,"height":10,"fx":-1,"fy":1,"cx":5,"cy":5,"near":0.1,"far":1}]})"},
      {"nearfar.json", R"({"candidates":[{"name":"a","position":[0,0,0],"quaternion":[1,0,0,0],"width":10,"height":10,"fx":1,"fy":1,"cx":5,"cy":5,"near":2,"far":1}]})"},
      {"unknown.json", R"({"candidates":[{"name":"a","position":[0,0,0],"quaternion":[1,0,0,0],"width":10,"height":10,"fx":1,"fy":1,"cx":5,"cy":5,"near":0.1,"far":1}],"results":[{"sensors":["zzz"]}]})"},
      {"zeroq.json", R"({"candidates":[{"name":"a","position":[0,0,0],"quaternion":[0,0,0,0],"width":10,"height":10,"fx":1,"fy":1,"cx":5,"cy":5,"near":0.1,"far":1}]})"},
      // Issue 15: [1e300, 1e300, 0, 0] overflowed the norm and normalised to zero; it is a
      // rotation of 90 degrees about x, so a candidate with it is accepted (below); these are not.
      {"nanq.json", R"({"candidates":[{"name":"a","position":[0,0,0],"quaternion":[1,0,0,1e400],"width":10,"height":10,"fx":1,"fy":1,"cx":5,"cy":5,"near":0.1,"far":1}]})"},
      {"primary.json", R"({"candidates":[{"name":"a","position":[0,0,0],"quaternion":[1,0,0,0],"width":10,"height":10,"fx":1,"fy":1,"cx":5,"cy":5,"near":0.1,"far":1}],"results":[{"sensors":["a"]}],"primary_result":3})"},
      {"twice.json", R"({"candidates":[{"name":"a","position":[0,0,0],"quaternion":[1,0,0,0],"width":10,"height":10,"fx":1,"fy":1,"cx":5,"cy":5,"near":0.1,"far":1}],"results":[{"sensors":["a","a"]}]})"},
  };
  for (const auto& [name, text] : cases) {
    test::WriteText(dir.File(name), text);
    try {
      LoadConstellation(dir.File(name));
      ADD_FAILURE() << name << " accepted";
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()).rfind(dir.File(name) + ":", 0), 0u) << e.what();
    }
  }
  // [1e300, 1e300, 0, 0] is w = x: a turn of 90 degrees about x, which maps y onto z.
  test::WriteText(dir.File("hugeq.json"), R"({"candidates":[{"name":"a","position":[0,0,0],"quaternion":[1e300,1e300,0,0],"width":10,"height":10,"fx":1,"fy":1,"cx":5,"cy":5,"near":0.1,"far":1}]})");
  const Constellation huge = LoadConstellation(dir.File("hugeq.json"));
  ASSERT_EQ(huge.sensors.size(), 1u);
  const Vec3 y_turned = huge.sensors[0].world_from_body.rotation * Vec3::UnitY();
  EXPECT_NEAR((y_turned - Vec3::UnitZ()).norm(), 0.0, 1e-12) << y_turned.transpose();
  // The syntax error is on line 3.
  try {
    LoadConstellation(dir.File("syntax.json"));
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(dir.File("syntax.json") + ":3:", 0), 0u) << e.what();
  }
}

}  // namespace
}  // namespace vantage
