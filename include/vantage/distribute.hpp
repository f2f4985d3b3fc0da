#pragma once
/// Beyond one process (docs/distributed.md), on the pipeline's TraceFunction: observe spread over
/// the ranks of an MPI job (`mpirun -np K vantage optimize|observe ...`), or over the tasks of a
/// job array as shards (`vantage observe --shard i/K`, then `vantage merge`). Either way the
/// candidates are split into contiguous ranges of about equal estimated cost, and the result is
/// byte for byte the one process's.
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "vantage/pipeline.hpp"
#include "vantage/visibility_file.hpp"

namespace vantage {

/// The estimated cost of tracing each candidate: the rays left after culling (CountRaysToTrace,
/// which grows with the resolution) plus a fixed overhead per candidate.
std::vector<uint64_t> TraceCosts(const Reference& reference, std::span<const Candidate> candidates,
                                 const ObserveOptions& options);

/// Splits `costs` into `parts` contiguous ranges of about equal total cost: parts + 1 boundaries,
/// the first 0 and the last costs.size(); part p is [b[p], b[p + 1]) and may be empty. Each part
/// is within one candidate's cost of its share.
std::vector<size_t> SplitByCost(std::span<const uint64_t> costs, size_t parts);

/// What a process was asked to do besides the scene it reads: the command and each option given
/// that shapes its result, one "--name value" text each, in a fixed order whatever the order on
/// the command line (the CLI's GivenSettings). Left out: what only says where (the scene's path,
/// --out, the folders searched: the content read is compared instead) or how fast (--threads).
/// The processes of one job, and the shards of one matrix, must have the same.
using RunSettings = std::vector<std::string>;

/// This build of vantage: the GNU build id of the binary (or module) holding this code, a hash
/// of all of it, so that two builds differ even at the same version; the version alone where the
/// linker wrote none. VANTAGE_TEST_BUILD_ID replaces it (the tests of mixed builds).
std::string BuildIdentity();

/// The first difference between two processes' settings, in words: "A has '--no-cull', B has
/// not" or "A has '--seed 7', B has '--seed 1'"; empty when they are the same.
std::string SettingsDifference(const RunSettings& a, const std::string& a_name,
                               const RunSettings& b, const std::string& b_name);

/// Shard i of K (`--shard i/K`).
struct ShardSpec {
  uint32_t index = 0;
  uint32_t count = 1;
};

/// Parses --shard: "i/K", or "env/K" for the index of a job array (SLURM_ARRAY_TASK_ID, else
/// JOB_COMPLETION_INDEX of a Kubernetes Indexed Job). InputError naming --shard.
ShardSpec ParseShard(const std::string& text);

/// `vantage observe --shard i/K`: ObserveRun tracing only shard i's candidates of each geometry.
/// The part records `settings`, the build and the fingerprint of every traced geometry, which
/// merge compares.
VisibilityShard ObserveShard(const ObserveRunOptions& options, const ShardSpec& shard,
                             const RunSettings& settings = {});

/// `vantage merge`: the visibility file of all shards, byte for byte the one process's once saved.
/// InputError naming the part and the first one that differ: another build, another option
/// (named), another scene content (the scene or a file it includes edited between the parts,
/// whatever their paths), other candidates or R; a repeated shard, another K, or the shard that
/// is missing.
VisibilityFile MergeShards(std::span<const std::string> paths);

/// Whether this process was started by an MPI launcher (mpirun, or srun with PMI/PMIx): read from
/// the launcher's environment, before MPI_Init. `ranks` gets the job's size when it is known.
bool LaunchedByMpi(int* ranks = nullptr);
/// Whether this vantage was built with MPI.
bool BuiltWithMpi();

/// Thrown on every rank once the ranks agreed to stop because one failed: `code` is the exit
/// status agreed on; what() is what this rank prints (empty: another rank reports).
class JobStopped : public std::runtime_error {
 public:
  JobStopped(int code, const std::string& message) : std::runtime_error(message), code_(code) {}
  int code() const { return code_; }

 private:
  int code_;
};

/// The MPI job of this process: MPI_Init on Start, MPI_Finalize on destruction. Every collective
/// step begins with the ranks' agreement (each one's status), so that one rank's failure ends the
/// job on all of them with one exit code and a message naming the rank.
class MpiJob {
 public:
  /// The job when this process was started by an MPI launcher (MPI_Init), else nullptr.
  /// InputError when started with several ranks by a vantage built without MPI.
  static std::unique_ptr<MpiJob> Start(int* argc, char*** argv);
  /// The started job of this process, or nullptr.
  static MpiJob* Current();
  ~MpiJob();
  MpiJob(const MpiJob&) = delete;
  MpiJob& operator=(const MpiJob&) = delete;

  int rank() const { return rank_; }
  int size() const { return size_; }

  /// The job's first agreement, before any rank reads its scene: every rank runs the same build
  /// (BuildIdentity) with the same settings. JobStopped with exit 2 and one message from rank 0
  /// naming the first rank and option that differ (issue 44: a quality filter or --refine on one
  /// rank only was mixed, or hung); the scene's content is compared when tracing (Tracer).
  void AgreeOnSettings(const RunSettings& settings);

  /// Each rank traces its share of the candidates (split by TraceCosts), the observation sets are
  /// gathered to rank 0 (MPI_Gatherv in chunks: its counts are 32-bit). Rank 0 returns them all,
  /// the others empty ones. JobStopped when a rank failed, or (exit 2) when the ranks trace
  /// another geometry (RayScene::GeometryFingerprint: the scene or a file it includes differs),
  /// other candidates, R or observe options.
  TraceFunction Tracer();

  /// --refine in a job: rank 0's tracer of the new poses, which only rank 0 knows. It sends them
  /// to the other ranks, waiting in ServeTraces, and then traces them as Tracer does.
  TraceFunction BroadcastTracer();
  /// The other ranks' side of BroadcastTracer while rank 0 selects and refines: traces each batch
  /// of poses rank 0 sends, in `rays` with `reference`, until rank 0 ends the job (Finish).
  void ServeTraces(const RayScene& rays, const Reference& reference, const ObserveOptions& options);

  /// The job's end: every rank gives its exit code and message (empty on success). Returns the
  /// code agreed on (the largest) and sets `print` to what this rank reports: its own failure,
  /// naming the rank, or once for all when every rank failed alike.
  int Finish(int code, const std::string& message, std::string* print);
  /// True once the ranks agreed to stop (JobStopped): no collective step follows.
  bool stopped() const { return stopped_; }

 private:
  MpiJob(int rank, int size) : rank_(rank), size_(size) {}
  int rank_ = 0;
  int size_ = 1;
  bool stopped_ = false;
  /// Rank 0's Finish as ServeTraces received it (the agreement of every rank's code), for this
  /// rank's Finish.
  std::vector<uint64_t> served_finish_;
  friend struct MpiJobAccess;
};

/// `vantage optimize` in this process: Optimize when it runs alone; in an MPI job the ranks agree
/// on `settings` (AgreeOnSettings), every rank observes its share and rank 0 alone selects,
/// assesses and returns the run (the others nullopt).
std::optional<RunResult> OptimizeInJob(const OptimizeOptions& options,
                                       const RunSettings& settings = {});
/// `vantage observe` likewise: rank 0 returns the matrix, the others nullopt.
std::optional<ObserveRunResult> ObserveInJob(const ObserveRunOptions& options,
                                             const RunSettings& settings = {});

}  // namespace vantage
