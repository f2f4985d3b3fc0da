#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>

#include "util/atomic_file.hpp"
#include "util/binary_io.hpp"
#include "util/cell_size.hpp"
#include "util/words.hpp"
#include "vantage/error.hpp"
#include "vantage/robot.hpp"
#include "vantage/visibility_file.hpp"

namespace vantage {
namespace {

// Layout: magic (8 bytes), format version (u32), payload, FNV-1a 64 of everything before it.
// Version 2 adds the selection settings (method, goal, k, budget) after the RANSAC ones;
// version 3 the quality filter after them, each sensor's depth-noise model, and per observation
// the plain cells and pixel counts of the quality filter (issue 9). Older files are still read,
// with what they lack at its default (no filter, no model: the catalog's by type id). Version 4
// adds per observation the pixel count of each cell (point density; empty when not recorded):
// older files read without counts, and --min-points refuses them. Version 5 adds each sensor's
// `interferes` flag (after its depth-noise model) and, after the candidates, the scene's mounting
// rules (keep-out boxes, min_separation, the count of candidates the boxes excluded): older files
// read with the flag unset (decided by the technology) and no rules, as they always behaved.
// Version 6 adds, after the mounting rules, R's target parts (names, each cell's part), each
// cell's exposure and --exposed-only's cells left out per part (issue 46): older files read
// without parts or exposure, which the report then does not show.
// Version 7 (issue 43, the physical sensor model) adds whether the observations were made with
// the physical model (after the quality filter), each sensor's second aperture (after its
// `interferes` flag) and per observation the cells the ideal pinhole would have counted (after
// its pixel counts): older files read as ideal, which they were.
// Version 8 adds, last in each candidate, its depth-noise model's incidence term (0: none) and
// its flying-pixel threshold (issue 43): older files read without either, as they were observed.
// Version 9 adds, after them, whether the sensor's unit cost was given (0 given, 1 not given:
// a catalog entry whose vendor publishes no price, or a type based on one without a `cost:`), so
// that `select --budget/--cheapest` refuses such a type as optimize does (issue 43). Older files
// read as before: the cost given unless the type id names an unpriced catalog entry.
// Version 10 adds, last, how observe read the scene: its absolute path, the model, resource and
// package folders (absolute), the --target names and the --cell-size override, so that `select`
// reloads the scene from any folder. Older files read without them (the scene as typed).
// Version 11 adds, last, each candidate's arm configuration (issue 45: the robot, its joints'
// names, the view's joints), so that `select` gives each result its tour as `optimize` does. It
// is written only when some candidate is on an arm: a file of fixed cameras stays version 10,
// byte for byte as before, and older vantage builds still read it.
constexpr char kMagic[8] = {'V', 'A', 'N', 'T', 'V', 'I', 'S', '\0'};
constexpr uint32_t kFormatVersion = 11;
constexpr uint32_t kFixedCamerasVersion = 10;  // written when no candidate is on an arm
constexpr uint32_t kOldestReadVersion = 1;

void WriteOptional(detail::BinaryWriter* w, const std::optional<double>& value) {
  w->U32(value ? 1 : 0);
  w->F64(value.value_or(0.0));
}


void WritePose(detail::BinaryWriter* w, const Pose& pose) {
  for (int a = 0; a < 3; ++a) w->F64(pose.position[a]);
  w->F64(pose.rotation.w());
  w->F64(pose.rotation.x());
  w->F64(pose.rotation.y());
  w->F64(pose.rotation.z());
}

// A sensor's second aperture: presence (0 unset, 1 set), kind, pose, field, disparity range.
void WriteAperture(detail::BinaryWriter* w, const std::optional<SecondAperture>& aperture) {
  w->U32(aperture ? 1 : 0);
  if (!aperture) return;
  const SecondAperture& a = *aperture;
  w->U32(static_cast<uint32_t>(a.kind));
  for (double v : {a.baseline, a.toe_in, a.hfov, a.vfov, a.cone}) w->F64(v);
  w->U32(static_cast<uint32_t>(a.width));
  w->U32(static_cast<uint32_t>(a.height));
  for (double v : {a.fx, a.fy, a.cx, a.cy}) w->F64(v);
  WriteOptional(w, a.disparity_range);
  w->Str(a.source);
}

template <typename Corrupt>
std::optional<double> ReadOptional(detail::BinaryReader* r, const char* what, const Corrupt& corrupt) {
  const uint32_t has_value = r->U32();
  const double value = r->F64();
  if (has_value > 1) throw corrupt(fmt::format("{} has a bad presence flag", what));
  return has_value ? std::optional<double>(value) : std::nullopt;
}

template <typename Corrupt>
std::optional<SecondAperture> ReadAperture(detail::BinaryReader* r, const Corrupt& corrupt) {
  const uint32_t present = r->U32();
  if (present > 1) throw corrupt("a second aperture has a bad presence flag");
  if (!present) return std::nullopt;
  SecondAperture a;
  const uint32_t kind = r->U32();
  if (kind > static_cast<uint32_t>(SecondAperture::Kind::kImager))
    throw corrupt("a second aperture's kind is unknown");
  a.kind = static_cast<SecondAperture::Kind>(kind);
  for (double* v : {&a.baseline, &a.toe_in, &a.hfov, &a.vfov, &a.cone}) *v = r->F64();
  a.width = static_cast<int>(r->U32());
  a.height = static_cast<int>(r->U32());
  for (double* v : {&a.fx, &a.fy, &a.cx, &a.cy}) *v = r->F64();
  a.disparity_range = ReadOptional(r, "disparity range", corrupt);
  a.source = r->Str();
  return a;  // checked with the sensor (SensorType::Validate)
}

Pose ReadPose(detail::BinaryReader* r) {
  Pose pose;
  for (int a = 0; a < 3; ++a) pose.position[a] = r->F64();
  const double w = r->F64(), x = r->F64(), y = r->F64(), z = r->F64();
  pose.rotation = Quat(w, x, y, z);
  return pose;
}

void WriteVec3(detail::BinaryWriter* w, const Vec3& v) {
  for (int a = 0; a < 3; ++a) w->F64(v[a]);
}

Vec3 ReadVec3(detail::BinaryReader* r) {
  Vec3 v;
  for (int a = 0; a < 3; ++a) v[a] = r->F64();
  return v;
}

// The scene's mounting rules (version 5): boxes (name, pose, min, max, file, line), then
// min_separation (opt, file, line), then the count of candidates the boxes excluded.
void WriteMounting(detail::BinaryWriter* w, const MountingRules& mounting, uint64_t kept_out) {
  w->U64(mounting.keep_out.size());
  for (const KeepOutBox& box : mounting.keep_out) {
    w->Str(box.name);
    WritePose(w, box.world_from_box);
    WriteVec3(w, box.min);
    WriteVec3(w, box.max);
    w->Str(box.file);
    w->U32(static_cast<uint32_t>(std::max(box.line, 0)));
  }
  WriteOptional(w, mounting.min_separation);
  w->Str(mounting.min_separation_file);
  w->U32(static_cast<uint32_t>(std::max(mounting.min_separation_line, 0)));
  w->U64(kept_out);
}

template <typename Corrupt>
void ReadMounting(detail::BinaryReader* r,
                  const Corrupt& corrupt,
                  MountingRules* mounting,
                  uint64_t* kept_out) {
  const uint64_t boxes = r->U64();
  r->CheckCount(boxes, 8 + 7 * 8 + 6 * 8 + 8 + 4);
  for (uint64_t i = 0; i < boxes; ++i) {
    KeepOutBox box;
    box.name = r->Str();
    box.world_from_box = ReadPose(r);
    box.min = ReadVec3(r);
    box.max = ReadVec3(r);
    box.file = r->Str();
    box.line = static_cast<int>(r->U32());
    const std::string where = fmt::format("keep-out box {} ('{}')", i, box.name);
    const Pose& pose = box.world_from_box;
    if (!pose.position.allFinite() || !pose.rotation.coeffs().allFinite() ||
        std::abs(pose.rotation.norm() - 1.0) > 1e-6)
      throw corrupt(where + ": its pose is not finite or its rotation not of length 1");
    if (!box.min.allFinite() || !box.max.allFinite() || !(box.min.array() < box.max.array()).all())
      throw corrupt(where + ": its corners are not finite or max does not exceed min");
    for (const std::string* text : {&box.name, &box.file}) {
      if (detail::FirstNonUtf8Byte(*text) != std::string::npos)
        throw corrupt(where + ": its name or file is not UTF-8");
      if (const std::string problem = detail::NameProblem(*text); !problem.empty())
        throw corrupt(fmt::format("{}: its name or file '{}' {}", where, detail::Escaped(*text),
                                  problem));
    }
    mounting->keep_out.push_back(std::move(box));
  }
  mounting->min_separation = ReadOptional(r, "min_separation", corrupt);
  mounting->min_separation_file = r->Str();
  mounting->min_separation_line = static_cast<int>(r->U32());
  // The scene readers' check (problem.hpp), so that a stored value is one a scene may give.
  if (mounting->min_separation) {
    if (const std::string problem = MinSeparationProblem(*mounting->min_separation);
        !problem.empty())
      throw corrupt("its " + problem);
  }
  if (detail::FirstNonUtf8Byte(mounting->min_separation_file) != std::string::npos)
    throw corrupt("its min_separation file is not UTF-8");
  *kept_out = r->U64();
}

void WriteSensor(detail::BinaryWriter* w, const SensorType& s) {
  w->Str(s.id);
  w->Str(s.name);
  w->Str(s.technology);
  w->U32(static_cast<uint32_t>(s.width));
  w->U32(static_cast<uint32_t>(s.height));
  for (double v : {s.fx, s.fy, s.cx, s.cy, s.near, s.far, s.fps, s.cost}) w->F64(v);
}

SensorType ReadSensor(detail::BinaryReader* r) {
  SensorType s;
  s.id = r->Str();
  s.name = r->Str();
  s.technology = r->Str();
  s.width = static_cast<int>(r->U32());
  s.height = static_cast<int>(r->U32());
  for (double* v : {&s.fx, &s.fy, &s.cx, &s.cy, &s.near, &s.far, &s.fps, &s.cost}) *v = r->F64();
  return s;
}

// A list of strings: its count (u64), then each (versions 6 and 10).
void WriteStrings(detail::BinaryWriter* w, const std::vector<std::string>& strings) {
  w->U64(strings.size());
  for (const std::string& s : strings) w->Str(s);
}

std::vector<std::string> ReadStrings(detail::BinaryReader* r) {
  const uint64_t count = r->U64();
  r->CheckCount(count, 8);
  std::vector<std::string> strings;
  for (uint64_t i = 0; i < count; ++i) strings.push_back(r->Str());
  return strings;
}

// R's parts and exposure (version 6): part names, each cell's part, each cell's exposure (as
// u32s), whether unexposed cells were left out, and how many per part.
void WriteParts(detail::BinaryWriter* w, const Reference& reference) {
  WriteStrings(w, reference.part_names);
  w->U32Vector(reference.part_of);
  w->U32Vector(std::vector<uint32_t>(reference.exposed.begin(), reference.exposed.end()));
  w->U32(reference.exposed_only ? 1 : 0);
  w->U64Vector(reference.left_out);
}

template <typename Corrupt>
void ReadParts(detail::BinaryReader* r, const Corrupt& corrupt, Reference* reference) {
  reference->part_names = ReadStrings(r);
  const uint64_t count = reference->part_names.size();
  reference->part_of = r->U32Vector();
  const std::vector<uint32_t> exposed = r->U32Vector();
  reference->exposed_only = r->U32() != 0;
  reference->left_out = r->U64Vector();
  const size_t cells = reference->keys.size();
  if (!reference->part_of.empty() && reference->part_of.size() != cells)
    throw corrupt("the reference's parts do not match its cells");
  if (std::any_of(reference->part_of.begin(), reference->part_of.end(),
                  [&](uint32_t part) { return part >= count; }))
    throw corrupt("a reference cell names a part the file does not have");
  if (!exposed.empty() && exposed.size() != cells)
    throw corrupt("the reference's exposure does not match its cells");
  if (std::any_of(exposed.begin(), exposed.end(), [](uint32_t e) { return e > 1; }))
    throw corrupt("a reference cell's exposure is neither 0 nor 1");
  reference->exposed.assign(exposed.begin(), exposed.end());
  if (reference->exposed_only ? reference->left_out.size() != count : !reference->left_out.empty())
    throw corrupt("the reference's cells left out do not match its parts");
}

// How the scene was read (version 10): the absolute path, the folders, targets and cell size.
void WriteSceneLoad(detail::BinaryWriter* w, const std::string& scene_path, const LoadOptions& load) {
  w->Str(scene_path);
  for (const auto* list : {&load.model_paths, &load.resource_paths, &load.package_paths, &load.targets})
    WriteStrings(w, *list);
  WriteOptional(w, load.cell_size);
}

template <typename Corrupt>
void ReadSceneLoad(detail::BinaryReader* r, const Corrupt& corrupt, VisibilityFile* file) {
  file->scene_path = r->Str();
  LoadOptions& load = file->load;
  for (auto* list : {&load.model_paths, &load.resource_paths, &load.package_paths, &load.targets})
    *list = ReadStrings(r);
  // Checked as --cell-size is (observe refused any other), so that the file is blamed, not an
  // option nobody gave when `select` reloads the scene.
  load.cell_size = ReadOptional(r, "the cell size override", corrupt);
  if (load.cell_size) {
    if (const std::string problem = detail::CellSizeProblem(*load.cell_size); !problem.empty())
      throw corrupt("the cell size override: " + problem);
  }
}

// The candidates' arm configurations (version 11): the distinct arms (robot, joint names) in
// order of first use, then per candidate 0 (a fixed camera) or 1 + its arm's row, and that
// arm's joints.
void WriteArmViews(detail::BinaryWriter* w, const VisibilityFile& file) {
  std::vector<StoredArmView> arms;
  std::vector<std::optional<StoredArmView>> views;
  std::vector<uint32_t> row;
  for (size_t i = 0; i < file.candidates.size(); ++i) {
    views.push_back(StoredArmViewOf(file, i));
    row.push_back(0);
    if (!views.back()) continue;
    const StoredArmView& view = *views.back();
    VANTAGE_CHECK(view.joints.size() == view.joint_names.size());
    const auto same = std::find_if(arms.begin(), arms.end(), [&](const StoredArmView& arm) {
      return arm.robot == view.robot && arm.joint_names == view.joint_names;
    });
    row.back() = static_cast<uint32_t>(same - arms.begin()) + 1;
    if (same == arms.end()) arms.push_back({view.robot, view.joint_names, {}});
  }
  w->U64(arms.size());
  for (const StoredArmView& arm : arms) {
    w->Str(arm.robot);
    WriteStrings(w, arm.joint_names);
  }
  for (size_t i = 0; i < views.size(); ++i) {
    w->U32(row[i]);
    if (views[i])
      for (double q : views[i]->joints) w->F64(q);
  }
}

template <typename Corrupt>
void ReadArmViews(detail::BinaryReader* r, const Corrupt& corrupt, VisibilityFile* file) {
  const uint64_t count = r->U64();
  r->CheckCount(count, 16);
  // Written only for a file with a camera on an arm.
  if (count == 0) throw corrupt("its arm configurations name no arm");
  std::vector<StoredArmView> arms;
  for (uint64_t a = 0; a < count; ++a) {
    StoredArmView arm;
    arm.robot = r->Str();
    arm.joint_names = ReadStrings(r);
    const std::string where = fmt::format("arm {} ('{}')", a, detail::Escaped(arm.robot));
    std::vector<const std::string*> texts{&arm.robot};
    for (const std::string& name : arm.joint_names) texts.push_back(&name);
    for (const std::string* text : texts) {
      if (detail::FirstNonUtf8Byte(*text) != std::string::npos)
        throw corrupt(where + ": its robot or a joint's name is not UTF-8");
      if (const std::string problem = detail::NameProblem(*text); !problem.empty() || text->empty())
        throw corrupt(fmt::format("{}: its robot or joint name '{}' {}", where,
                                  detail::Escaped(*text), problem.empty() ? "is empty" : problem));
    }
    if (arm.joint_names.empty()) throw corrupt(where + ": it has no joint");
    if (std::set<std::string>(arm.joint_names.begin(), arm.joint_names.end()).size() !=
        arm.joint_names.size())
      throw corrupt(where + ": a joint is named twice");
    arms.push_back(std::move(arm));
  }
  file->arm_views.assign(file->candidates.size(), std::nullopt);
  for (size_t i = 0; i < file->candidates.size(); ++i) {
    const uint32_t row = r->U32();
    if (row == 0) continue;
    const Candidate& c = file->candidates[i];
    const std::string where = fmt::format("candidate {} ('{}')", i, c.name);
    if (row > arms.size())
      throw corrupt(fmt::format("{}: its arm {} is not one of the file's {}", where, row,
                                arms.size()));
    // `select` finds the arm by the candidate's population, as optimize does.
    if (c.population.empty()) throw corrupt(where + ": a camera on an arm of no population");
    StoredArmView view = arms[row - 1];
    for (size_t j = 0; j < view.joint_names.size(); ++j) {
      const double q = r->F64();
      // As the URDF's limits are (kMaxJointTravel).
      if (!(std::abs(q) <= kMaxJointTravel))
        throw corrupt(fmt::format("{}: joint '{}' at {} is not a position within ±1e6 [rad or m]",
                                  where, view.joint_names[j], q));
      view.joints.push_back(q);
    }
    file->arm_views[i] = std::move(view);
  }
}

bool StrictlyIncreasing(const std::vector<uint64_t>& keys) {
  return std::adjacent_find(keys.begin(), keys.end(),
                            [](uint64_t a, uint64_t b) { return a >= b; }) == keys.end();
}

// The whole file (magic to checksum); with `observations` false, every observation written empty
// (the fingerprint of what the matrix was made from).
std::string EncodeVisibilityFile(const VisibilityFile& file, bool observations) {
  bool on_arms = false;
  for (size_t i = 0; i < file.candidates.size() && !on_arms; ++i)
    on_arms = StoredArmViewOf(file, i).has_value();
  detail::BinaryWriter w;
  w.Bytes(kMagic, sizeof(kMagic));
  w.U32(on_arms ? kFormatVersion : kFixedCamerasVersion);
  w.Str(file.scene);
  w.U64(file.seed);
  const SelectionSettings& settings = file.selection;
  w.U32(static_cast<uint32_t>(settings.n));
  w.U32(static_cast<uint32_t>(settings.ransac_iterations));
  w.F64(settings.ransac_stop_coverage);
  // Unset is the command's default, "all", as files have always said.
  w.Str(settings.method ? MethodName(*settings.method) : "all");
  WriteOptional(&w, settings.goal);
  w.U32(static_cast<uint32_t>(settings.k));
  WriteOptional(&w, settings.budget);
  WriteOptional(&w, file.quality.max_incidence_deg);
  WriteOptional(&w, file.quality.max_depth_noise);
  w.U32(file.physical ? 1 : 0);
  w.F64(file.reference.cell_size);
  w.U64Vector(file.reference.keys);
  w.U64(file.candidates.size());
  VANTAGE_CHECK(file.observations.size() == file.candidates.size());
  for (size_t i = 0; i < file.candidates.size(); ++i) {
    const Candidate& c = file.candidates[i];
    w.Str(c.name);
    w.Str(c.type_id);
    w.Str(c.population);
    WriteSensor(&w, c.sensor);
    const std::optional<DepthNoise>& noise = c.sensor.depth_noise;
    w.U32(noise ? 1 : 0);
    for (double v : {noise ? noise->a : 0.0, noise ? noise->b : 0.0, noise ? noise->c : 0.0}) w.F64(v);
    w.Str(noise ? noise->source : std::string());
    // interferes: 0 unset (by the technology), 1 false, 2 true.
    w.U32(c.sensor.interferes ? (*c.sensor.interferes ? 2 : 1) : 0);
    WriteAperture(&w, c.sensor.second_aperture);
    WritePose(&w, c.world_from_body);
    static const Observation kNone;
    const Observation& o = observations ? file.observations[i] : kNone;
    w.U32Vector(o.reference_indices);
    w.U64Vector(o.outside_keys);
    w.U64(o.rays_traced);
    w.U32Vector(o.plain_reference_indices);
    w.U64(o.target_pixels);
    w.U64(o.quality_pixels);
    w.U16Vector(o.reference_hits);
    w.U32(o.ideal_differs ? 1 : 0);
    w.U32Vector(o.ideal_reference_indices);
    // Format 8: the noise model's incidence term, the flying-pixel threshold.
    w.F64(noise ? noise->incidence : 0.0);
    WriteOptional(&w, c.sensor.flying_pixel_threshold);
    // Format 9: 1 when the unit cost is not given (0, the common case, keeps files compact).
    w.U32(c.sensor.cost_given ? 0 : 1);
  }
  WriteMounting(&w, file.mounting, file.kept_out);
  WriteParts(&w, file.reference);
  // Format 10: how the scene was read; empty in the fingerprint (see VisibilityFile::load).
  static const LoadOptions kNoLoad;
  WriteSceneLoad(&w, observations ? file.scene_path : std::string(),
                 observations ? file.load : kNoLoad);
  if (on_arms) WriteArmViews(&w, file);  // format 11
  w.U64(detail::Fnv1a64(w.data()));
  return w.data();
}

// The file of `bytes`, read from `path` (for messages).
VisibilityFile DecodeVisibilityFile(const std::string& bytes, const std::string& path) {
  const auto corrupt = [&](const std::string& what) {
    return InputError(AtPlace(path, 0, what + " — recreate it with `vantage observe`"));
  };
  if (bytes.size() < sizeof(kMagic) + 4 + 8 || std::memcmp(bytes.data(), kMagic, sizeof(kMagic)) != 0)
    throw corrupt("not a vantage visibility file");
  const std::string_view body(bytes.data(), bytes.size() - 8);
  uint64_t stored = 0;
  std::memcpy(&stored, bytes.data() + body.size(), 8);
  detail::BinaryReader r(body, path);
  r.Skip(sizeof(kMagic));
  const uint32_t version = r.U32();
  if (version < kOldestReadVersion || version > kFormatVersion)
    throw corrupt(fmt::format(
        "visibility file format version {}, this vantage reads versions {} to {}", version,
        kOldestReadVersion, kFormatVersion));
  if (stored != detail::Fnv1a64(body)) throw corrupt("checksum mismatch: the file is corrupt");

  VisibilityFile file;
  file.scene = r.Str();
  file.seed = r.U64();
  SelectionSettings& settings = file.selection;
  settings.n = static_cast<int>(r.U32());
  settings.ransac_iterations = static_cast<int>(r.U32());
  settings.ransac_stop_coverage = r.F64();
  if (version >= 2) {
    const std::string method = r.Str();
    if (!method.empty()) {
      try {
        settings.method = ParseMethod(method);
      } catch (const InputError&) {
        // Named as a field of the file, beside the file (ParseMethod's own text names neither).
        std::string names;
        for (const Method m : {Method::kBest, Method::kRansac, Method::kGreedy, Method::kLocal,
                               Method::kExact, Method::kAll})
          names += (names.empty() ? "" : ", ") + MethodName(m);
        throw corrupt(fmt::format("its stored settings.method '{}' is unknown (valid: {})",
                                  method, names));
      }
    }
    settings.goal = ReadOptional(&r, "goal", corrupt);
    settings.k = static_cast<int>(r.U32());
    settings.budget = ReadOptional(&r, "budget", corrupt);
    if (settings.k < 1) throw corrupt("k is not a positive integer");
  }
  if (version >= 3) {
    file.quality.max_incidence_deg = ReadOptional(&r, "max incidence", corrupt);
    file.quality.max_depth_noise = ReadOptional(&r, "max depth noise", corrupt);
    try {
      file.quality.Validate();
    } catch (const InputError& e) {
      throw corrupt(fmt::format("its quality filter: {}", e.what()));
    }
  }
  if (version >= 7) {
    const uint32_t physical = r.U32();
    if (physical > 1) throw corrupt("its sensor model flag is not 0 or 1");
    file.physical = physical == 1;
  }
  file.reference.cell_size = r.F64();
  if (!std::isfinite(file.reference.cell_size) || !(file.reference.cell_size > 0))
    throw corrupt(
        fmt::format("cell size {} is not a positive finite length", file.reference.cell_size));
  // The check of every cell size (util/cell_size.hpp): select re-traces the chosen sensors for
  // the robustness read-out, and 1e300 m voxelised their hits wrongly (issue 15).
  if (const std::string problem = detail::CellSizeProblem(file.reference.cell_size);
      !problem.empty())
    throw corrupt(problem);
  file.reference.keys = r.U64Vector();
  if (!StrictlyIncreasing(file.reference.keys))
    throw corrupt("the reference keys are not sorted and unique");
  const uint64_t count = r.U64();
  r.CheckCount(count, 64);
  std::set<std::string> names;
  for (uint64_t i = 0; i < count; ++i) {
    Candidate c;
    c.name = r.Str();
    c.type_id = r.Str();
    c.population = r.Str();
    c.sensor = ReadSensor(&r);
    // Names go into report.json as they are: UTF-8 like the scene files they came from (issue
    // 15: a Latin-1 name was written with U+FFFD, no longer the candidate's name).
    for (const auto& [field, text] :
         {std::pair<const char*, const std::string*>{"name", &c.name},
          {"type id", &c.type_id}, {"population", &c.population}, {"sensor id", &c.sensor.id},
          {"sensor name", &c.sensor.name}, {"sensor technology", &c.sensor.technology}}) {
      if (const size_t at = detail::FirstNonUtf8Byte(*text); at != std::string::npos)
        throw corrupt(fmt::format("candidate {}: its {} has byte 0x{:02X}, which is not UTF-8", i,
                                  field, static_cast<unsigned char>((*text)[at])));
      // The scene readers' check: a newline in a name breaks candidates.csv (issue 15).
      if (const std::string problem = detail::NameProblem(*text); !problem.empty())
        throw corrupt(fmt::format("candidate {}: its {} '{}' {}", i, field,
                                  detail::Escaped(*text), problem));
    }
    if (c.name.empty()) throw corrupt(fmt::format("candidate {}: its name is empty", i));
    if (version >= 3) {
      const uint32_t has_noise = r.U32();
      DepthNoise noise;
      noise.a = r.F64();
      noise.b = r.F64();
      noise.c = r.F64();
      noise.source = r.Str();
      if (has_noise > 1) throw corrupt("a depth noise model has a bad presence flag");
      if (has_noise) c.sensor.depth_noise = std::move(noise);
    }
    if (version >= 5) {
      const uint32_t interferes = r.U32();
      if (interferes > 2) throw corrupt("a sensor's interferes flag is not 0, 1 or 2");
      if (interferes > 0) c.sensor.interferes = interferes == 2;
    }
    if (version >= 7) c.sensor.second_aperture = ReadAperture(&r, corrupt);
    c.world_from_body = ReadPose(&r);
    Observation o;
    o.reference_indices = r.U32Vector();
    o.outside_keys = r.U64Vector();
    o.rays_traced = r.U64();
    if (version >= 3) {
      o.plain_reference_indices = r.U32Vector();
      o.target_pixels = r.U64();
      o.quality_pixels = r.U64();
    }
    if (version >= 4) o.reference_hits = r.U16Vector();
    if (version >= 7) {
      const uint32_t differs = r.U32();
      if (differs > 1) throw corrupt("an observation's ideal flag is not 0 or 1");
      o.ideal_differs = differs == 1;
      o.ideal_reference_indices = r.U32Vector();
      if (!o.ideal_differs && !o.ideal_reference_indices.empty())
        throw corrupt("an observation holds ideal cells without its ideal flag");
    }
    if (version >= 8) {
      const double incidence = r.F64();
      if (c.sensor.depth_noise) {
        c.sensor.depth_noise->incidence = incidence;
      } else if (incidence != 0) {
        throw corrupt("an incidence term without a depth noise model");
      }
      c.sensor.flying_pixel_threshold = ReadOptional(&r, "flying-pixel threshold", corrupt);
    }
    if (version >= 9) {
      const uint32_t cost_not_given = r.U32();
      if (cost_not_given > 1) throw corrupt("a sensor's cost-given flag is not 0 or 1");
      c.sensor.cost_given = cost_not_given == 0;
    }
    const auto check_indices = [&](const std::vector<uint32_t>& indices) {
      for (size_t k = 0; k < indices.size(); ++k) {
        if (indices[k] >= file.reference.keys.size() || (k > 0 && indices[k] <= indices[k - 1]))
          throw corrupt("observation indices out of range or unsorted");
      }
    };
    check_indices(o.reference_indices);
    check_indices(o.plain_reference_indices);
    check_indices(o.ideal_reference_indices);
    if (!o.reference_hits.empty() && !o.has_point_counts())
      throw corrupt("an observation's point counts do not match its cells");
    const std::string where = fmt::format("candidate {} ('{}')", i, c.name);
    if (o.quality_pixels > o.target_pixels || o.target_pixels > o.rays_traced)
      throw corrupt(where + ": its pixel counts contradict each other");
    if (!StrictlyIncreasing(o.outside_keys))
      throw corrupt(where + ": its outside keys are not sorted and unique");
    try {
      c.sensor.Validate();
    } catch (const InputError& e) {
      throw corrupt(fmt::format("{}: {}", where, e.what()));
    }
    const Pose& pose = c.world_from_body;
    if (!pose.position.allFinite() || !pose.rotation.coeffs().allFinite())
      throw corrupt(where + ": its pose is not finite");
    if (std::abs(pose.rotation.norm() - 1.0) > 1e-6)
      throw corrupt(fmt::format("{}: its rotation quaternion has length {}, not 1", where,
                                pose.rotation.norm()));
    if (!names.insert(c.name).second) throw corrupt(where + ": the name is used twice");
    file.candidates.push_back(std::move(c));
    file.observations.push_back(std::move(o));
  }
  if (version >= 5) ReadMounting(&r, corrupt, &file.mounting, &file.kept_out);
  if (version >= 6) ReadParts(&r, corrupt, &file.reference);
  if (version >= 10) ReadSceneLoad(&r, corrupt, &file);
  if (version >= 11) ReadArmViews(&r, corrupt, &file);
  if (!r.AtEnd()) throw corrupt("trailing bytes after the payload");
  return file;
}

// A shard: its own magic and version, index, count, fingerprint, the candidates it observed,
// then the whole visibility file (with its own checksum), then (version 2) the geometry's
// fingerprint, the build and the settings, then FNV-1a 64 of everything before.
constexpr char kShardMagic[8] = {'V', 'A', 'N', 'T', 'P', 'R', 'T', '\0'};
constexpr uint32_t kShardVersion = 2;

}  // namespace

std::optional<StoredArmView> StoredArmViewOf(const VisibilityFile& file, size_t candidate) {
  const Candidate& c = file.candidates.at(candidate);
  if (c.arm && c.arm->body)
    return StoredArmView{c.arm->body->robot, c.arm->body->joint_names, c.arm->joints};
  if (candidate < file.arm_views.size()) return file.arm_views[candidate];
  return std::nullopt;
}

void SaveVisibilityFile(const std::string& path, const VisibilityFile& file) {
  detail::WriteFileAtomically(path, EncodeVisibilityFile(file, true));
}

VisibilityFile LoadVisibilityFile(const std::string& path) {
  // ReadInputFile refuses a device or a pipe before reading it (issue 15: /dev/zero ran out of
  // memory).
  VisibilityFile file =
      DecodeVisibilityFile(detail::ReadInputFile(path, "visibility file"), path);
  // observe never writes an empty R (a scene without target cells is refused); with one, every
  // coverage would be 0 % of nothing (issue 15). Only a file: MPI's messages of poses carry none.
  if (file.reference.keys.empty())
    throw InputError(AtPlace(path, 0, "its reference R has no cell — recreate it with `vantage observe`"));
  return file;
}

std::string EncodeVisibility(const VisibilityFile& file) {
  return EncodeVisibilityFile(file, true);
}

VisibilityFile DecodeVisibility(const std::string& bytes, const std::string& where) {
  return DecodeVisibilityFile(bytes, where);
}

uint64_t VisibilityFingerprint(const VisibilityFile& file) {
  return detail::Fnv1a64(EncodeVisibilityFile(file, false));
}

void SaveVisibilityShard(const std::string& path, const VisibilityShard& shard) {
  VANTAGE_CHECK(shard.index < shard.count);
  detail::BinaryWriter w;
  w.Bytes(kShardMagic, sizeof(kShardMagic));
  w.U32(kShardVersion);
  w.U32(shard.index);
  w.U32(shard.count);
  w.U64(shard.fingerprint);
  w.U32Vector(shard.candidates);
  w.Str(EncodeVisibilityFile(shard.file, true));
  w.U64(shard.geometry);
  w.Str(shard.build);
  w.U32(static_cast<uint32_t>(shard.settings.size()));
  for (const std::string& setting : shard.settings) w.Str(setting);
  w.U64(detail::Fnv1a64(w.data()));
  detail::WriteFileAtomically(path, w.data());
}

VisibilityShard LoadVisibilityShard(const std::string& path) {
  const std::string bytes = detail::ReadInputFile(path, "shard");
  const auto corrupt = [&](const std::string& what) {
    return InputError(AtPlace(
        path, 0, what + " — write the parts with `vantage observe SCENE --shard i/K --out FILE`"));
  };
  if (bytes.size() < sizeof(kShardMagic) + 8 ||
      std::memcmp(bytes.data(), kShardMagic, sizeof(kShardMagic)) != 0)
    throw corrupt("not a shard of a visibility file");
  const std::string_view body(bytes.data(), bytes.size() - 8);
  uint64_t stored = 0;
  std::memcpy(&stored, bytes.data() + body.size(), 8);
  if (stored != detail::Fnv1a64(body)) throw corrupt("checksum mismatch: the shard is corrupt");
  detail::BinaryReader r(body, path);
  r.Skip(sizeof(kShardMagic));
  const uint32_t version = r.U32();
  if (version != kShardVersion)
    throw corrupt(fmt::format("shard format version {}, this vantage reads version {}", version,
                              kShardVersion));
  VisibilityShard shard;
  shard.index = r.U32();
  shard.count = r.U32();
  shard.fingerprint = r.U64();
  shard.candidates = r.U32Vector();
  shard.file = DecodeVisibilityFile(r.Str(), path);
  shard.geometry = r.U64();
  shard.build = r.Str();
  const uint32_t settings = r.U32();
  for (uint32_t k = 0; k < settings && !r.AtEnd(); ++k) shard.settings.push_back(r.Str());
  if (shard.settings.size() != settings) throw corrupt("its settings are cut short");
  if (!r.AtEnd()) throw corrupt("trailing bytes after the payload");
  if (shard.count == 0 || shard.index >= shard.count)
    throw corrupt(fmt::format("shard {}/{} is no shard", shard.index, shard.count));
  for (size_t k = 0; k < shard.candidates.size(); ++k) {
    if (shard.candidates[k] >= shard.file.candidates.size() ||
        (k > 0 && shard.candidates[k] <= shard.candidates[k - 1]))
      throw corrupt("its candidate indices are out of range or unsorted");
  }
  return shard;
}

}  // namespace vantage
