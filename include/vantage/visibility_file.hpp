#pragma once
/// The visibility matrix with what it was made from, as the versioned `.vis` file that lets
/// `vantage select` rerun selection without re-rendering (SYSTEM.md, pipeline stage 4).
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "vantage/candidates.hpp"
#include "vantage/problem.hpp"
#include "vantage/reference.hpp"
#include "vantage/settings.hpp"
#include "vantage/visibility.hpp"

namespace vantage {

/// A camera on an arm as a visibility file keeps it (format version 11): the robot that carries
/// it, the robot's settable joints (ArmBody::joint_names) and the view's configuration. The link
/// poses and meshes are not kept: `vantage select` rebuilds them from the reloaded scene's robot.
struct StoredArmView {
  std::string robot;
  std::vector<std::string> joint_names;
  std::vector<double> joints;  ///< one per joint name [rad or m]
  bool operator==(const StoredArmView&) const = default;
};

/// Everything `vantage select` needs to rerun selection without re-rendering.
struct VisibilityFile {
  std::string scene;  ///< path of the scene it came from
  uint64_t seed = 1;
  /// The scene's selection settings (n and RANSAC's since format version 1, method, goal, k and
  /// budget since version 2; older files read as the defaults).
  SelectionSettings selection;
  Reference reference;
  std::vector<Candidate> candidates;
  std::vector<Observation> observations;  ///< one per candidate
  QualityFilter quality;  ///< the filter the observations were made with (format version 3)
  /// Whether the observations were made with the physical sensor model (issue 43; format
  /// version 6, older files: ideal). Re-tracing (robustness, refinement) uses the same model.
  bool physical = false;
  /// The scene's mounting rules (format version 5; older files: none): `vantage select` applies
  /// its min_separation and reports its keep-out boxes as `optimize` on the scene does
  /// (docs/constraints.md). Each candidate's `sensor.interferes` is kept from version 5 too.
  MountingRules mounting;
  /// How many candidates the keep-out boxes excluded before observing (not in `candidates`).
  uint64_t kept_out = 0;
  /// How observe read the scene (format version 10; older files and external matrices: empty):
  /// its absolute path, and the options given with their folders absolute, so that `vantage
  /// select` reloads the same scene from any folder (the page's meshes, the re-traced fields of
  /// view and pose tolerance) where `scene`, as typed, named it from observe's folder only. Left
  /// out of the fingerprint: shards of one run observed from other folders still agree.
  std::string scene_path;
  LoadOptions load;
  /// Per candidate, its arm configuration as read from the file (format version 11; empty when
  /// the file holds none: every older file, and every file of fixed cameras only). Candidates read
  /// from a file have no Candidate::arm; `vantage select` gives them one from these and the
  /// reloaded scene. The writer takes a candidate's Candidate::arm where it has one, else this.
  std::vector<std::optional<StoredArmView>> arm_views;
};

/// A candidate's arm configuration as the file keeps it: from Candidate::arm when set, else from
/// `arm_views` (a file read back); nullopt for a fixed camera.
std::optional<StoredArmView> StoredArmViewOf(const VisibilityFile& file, size_t candidate);

/// Writes the versioned binary file (magic, version, payload, FNV-1a 64 checksum) atomically:
/// format version 11 when some candidate is on an arm, else 10 (the same bytes as before arms
/// were kept, which older vantage builds still read).
void SaveVisibilityFile(const std::string& path, const VisibilityFile& file);
/// Reads it back; InputError naming the file when it is not one, corrupt, or another version.
VisibilityFile LoadVisibilityFile(const std::string& path);

/// The bytes SaveVisibilityFile writes, and back (`where` names their source in messages, as the
/// path does for LoadVisibilityFile): a file sent from one process to another.
std::string EncodeVisibility(const VisibilityFile& file);
VisibilityFile DecodeVisibility(const std::string& bytes, const std::string& where);

/// FNV-1a 64 of everything the file holds but its observations: the scene, seed, settings, quality
/// filter, R and the candidates. Equal for the shards of one run, different for another scene or
/// other settings.
uint64_t VisibilityFingerprint(const VisibilityFile& file);

/// One part of a visibility file observed in shards (`vantage observe SCENE --shard i/K`,
/// docs/distributed.md): the whole file with only this shard's candidates observed.
struct VisibilityShard {
  uint32_t index = 0;                ///< i of i/K
  uint32_t count = 1;                ///< K
  /// VisibilityFingerprint(file) without the scene's path: parts of one scene content observed
  /// from two paths merge, parts of an edited scene do not (shard format version 2).
  uint64_t fingerprint = 0;
  /// Every traced geometry's RayScene::GeometryFingerprint, combined in trace order: the scene's
  /// content and every file it includes, as traced (version 2).
  uint64_t geometry = 0;
  std::string build;                  ///< the vantage build that observed it (version 2)
  std::vector<std::string> settings;  ///< the command's settings (RunSettings, version 2)
  std::vector<uint32_t> candidates;  ///< the candidates this shard observed, ascending
  VisibilityFile file;               ///< the other candidates' observations are empty
};

/// Writes a shard (its own magic and version, the file inside, a checksum) atomically.
void SaveVisibilityShard(const std::string& path, const VisibilityShard& shard);
/// Reads it back; InputError naming the file when it is not one, corrupt, or another version.
VisibilityShard LoadVisibilityShard(const std::string& path);

}  // namespace vantage
