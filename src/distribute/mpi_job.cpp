// The MPI job (docs/distributed.md): detection before MPI_Init, the ranks' agreement before each
// collective step, the traced share gathered to rank 0 in chunks, and the job's end.
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <climits>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <thread>

#include "vantage/distribute.hpp"
#include "vantage/error.hpp"

#ifdef VANTAGE_HAVE_MPI
#include <mpi.h>
#endif

namespace vantage {
namespace {

MpiJob* g_job = nullptr;

int EnvInt(const char* name, int fallback) {
  const char* value = std::getenv(name);
  return value ? std::atoi(value) : fallback;
}

}  // namespace

bool LaunchedByMpi(int* ranks) {
  // Open MPI's mpirun, PMIx launchers (Open MPI 4+, Slurm --mpi=pmix), PMI (MPICH, Slurm pmi2).
  for (const char* size : {"OMPI_COMM_WORLD_SIZE", "PMIX_SIZE", "PMI_SIZE"}) {
    if (std::getenv(size)) {
      if (ranks) *ranks = EnvInt(size, 1);
      return true;
    }
  }
  if (std::getenv("PMIX_RANK") || std::getenv("PMI_RANK")) {
    if (ranks) *ranks = 0;  // unknown until MPI_Init
    return true;
  }
  return false;
}

MpiJob* MpiJob::Current() { return g_job; }

std::optional<RunResult> OptimizeInJob(const OptimizeOptions& options,
                                       const RunSettings& settings) {
  MpiJob* job = MpiJob::Current();
  if (!job) return Optimize(options);
  job->AgreeOnSettings(settings);
  OptimizeOptions spread = options;
  spread.trace = job->Tracer();
  if (spread.refine && job->rank() == 0) spread.refine->trace = job->BroadcastTracer();
  OptimizeObserved observed = ObserveForOptimize(spread);
  if (job->rank() != 0) {
    // Rank 0 selects; its refinement's new poses are traced by every rank, as observe's were.
    if (spread.refine) {
      ObserveOptions refine_observe = spread.observe;  // as FinishOptimize traces them
      refine_observe.progress = nullptr;
      job->ServeTraces(*observed.observed.rays, observed.observed.data.reference, refine_observe);
    }
    return std::nullopt;
  }
  return FinishOptimize(spread, std::move(observed));
}

std::optional<ObserveRunResult> ObserveInJob(const ObserveRunOptions& options,
                                             const RunSettings& settings) {
  MpiJob* job = MpiJob::Current();
  if (!job) return ObserveRun(options);
  job->AgreeOnSettings(settings);
  ObserveRunOptions spread = options;
  spread.trace = job->Tracer();
  ObserveRunResult result = ObserveRun(spread);
  if (job->rank() != 0) return std::nullopt;
  return result;
}

#ifndef VANTAGE_HAVE_MPI

bool BuiltWithMpi() { return false; }

std::unique_ptr<MpiJob> MpiJob::Start(int*, char***) {
  int ranks = 0;
  if (!LaunchedByMpi(&ranks) || ranks == 1) return nullptr;
  throw InputError(
      "mpirun: this vantage was built without MPI — install libopenmpi-dev "
      "(scripts/install-deps.sh) and rebuild, run it without mpirun, or split the work with "
      "`vantage observe --shard i/K` and `vantage merge` (docs/distributed.md)");
}

MpiJob::~MpiJob() = default;

void MpiJob::AgreeOnSettings(const RunSettings&) {}
TraceFunction MpiJob::Tracer() { return {}; }
TraceFunction MpiJob::BroadcastTracer() { return {}; }
void MpiJob::ServeTraces(const RayScene&, const Reference&, const ObserveOptions&) {}

int MpiJob::Finish(int code, const std::string& message, std::string* print) {
  *print = message;
  return code;
}

#else  // VANTAGE_HAVE_MPI

bool BuiltWithMpi() { return true; }

// Reaches the job's private state from the helpers below.
struct MpiJobAccess {
  static void Stop(MpiJob* job) { job->stopped_ = true; }
};

namespace {

// kPhaseServe: waiting in ServeTraces for rank 0, which says kPhaseRefine (poses follow) or
// kPhaseFinish (the job ends). kPhaseStart: AgreeOnSettings, before the scene is read.
constexpr uint64_t kPhaseTrace = 1, kPhaseTraced = 2, kPhaseFinish = 3, kPhaseServe = 4,
                   kPhaseRefine = 5, kPhaseStart = 6;

// What each rank says at an agreement: its exit code so far, a hash of its message, two
// fingerprints of its inputs, and where it is. At kPhaseStart `first` is the settings' and
// `second` the build's; at kPhaseTrace the traced geometry's and that of R, the candidates and
// the observe options; at kPhaseRefine `first` is the size of the poses that follow.
struct Vote {
  uint64_t code = 0;
  uint64_t message_hash = 0;
  uint64_t first = 0;
  uint64_t phase = 0;
  uint64_t second = 0;
};
constexpr int kVoteWords = sizeof(Vote) / sizeof(uint64_t);
static_assert(sizeof(Vote) == kVoteWords * sizeof(uint64_t));

uint64_t Fnv(const void* data, size_t n, uint64_t hash = 1469598103934665603ull) {
  const auto* bytes = static_cast<const unsigned char*>(data);
  for (size_t i = 0; i < n; ++i) hash = (hash ^ bytes[i]) * 1099511628211ull;
  return hash;
}

uint64_t HashText(const std::string& text) { return Fnv(text.data(), text.size()); }

// What the ranks trace with must be the same everywhere besides the geometry: R, every candidate
// as a visibility file holds it (pose, sensor type, noise model, name) and the observe options.
uint64_t InputFingerprint(const Reference& reference, std::span<const Candidate> candidates,
                          const ObserveOptions& options) {
  VisibilityFile inputs;
  inputs.reference = reference;
  inputs.candidates.assign(candidates.begin(), candidates.end());
  inputs.observations.resize(candidates.size());  // not hashed; the encoder wants one each
  inputs.quality = options.quality;
  const uint64_t flags[] = {options.cull, options.count_points};
  return Fnv(flags, sizeof(flags), VisibilityFingerprint(inputs));
}

std::string JoinSettings(const RunSettings& settings) {
  std::string text;
  for (const std::string& setting : settings) text += setting + '\n';
  return text;
}

RunSettings SplitSettings(const std::string& text) {
  RunSettings settings;
  for (size_t at = 0; at < text.size();) {
    const size_t end = text.find('\n', at);
    settings.push_back(text.substr(at, end - at));
    at = end == std::string::npos ? text.size() : end + 1;
  }
  return settings;
}

// Waits for a non-blocking collective without spinning a core: a rank that waits (rank 0 for
// the others' shares, the others while rank 0 selects) leaves the CPU to the ranks that work.
void Wait(MPI_Request* request) {
  int done = 0;
  auto pause = std::chrono::microseconds(50);
  while (true) {
    MPI_Test(request, &done, MPI_STATUS_IGNORE);
    if (done) return;
    std::this_thread::sleep_for(pause);
    pause = std::min(pause * 2, std::chrono::microseconds(20000));
  }
}

std::vector<Vote> Agree(const Vote& mine, int size) {
  std::vector<Vote> all(static_cast<size_t>(size));
  MPI_Request request;
  MPI_Iallgather(&mine, kVoteWords, MPI_UINT64_T, all.data(), kVoteWords, MPI_UINT64_T,
                 MPI_COMM_WORLD, &request);
  Wait(&request);
  return all;
}

// What this rank prints of a failure: its own message naming it, or, when every rank failed
// alike, the message once (rank 0).
std::string Attribution(const std::vector<Vote>& votes, int rank, const std::string& message) {
  const Vote& mine = votes[static_cast<size_t>(rank)];
  if (mine.code == 0 || message.empty()) return {};  // empty: already reported (CLI11's own)
  const bool alike = std::all_of(votes.begin(), votes.end(), [&](const Vote& v) {
    return v.code == mine.code && v.message_hash == mine.message_hash;
  });
  if (alike && votes.size() > 1)
    return rank == 0 ? fmt::format("every rank of {}: {}", votes.size(), message) : std::string();
  return fmt::format("rank {} of {}: {}", rank, votes.size(), message);
}

uint64_t AgreedCode(const std::vector<Vote>& votes) {
  uint64_t code = 0;
  for (const Vote& v : votes) code = std::max(code, v.code);
  return code;
}

// The observations of a share as bytes: per candidate its counts, then its five lists.
std::string Encode(std::span<const Observation> observations) {
  std::string bytes;
  const auto put = [&](const void* p, size_t n) { bytes.append(static_cast<const char*>(p), n); };
  for (const Observation& o : observations) {
    const uint64_t header[] = {o.reference_indices.size(), o.outside_keys.size(),
                               o.plain_reference_indices.size(), o.rays_traced,
                               o.target_pixels, o.quality_pixels, o.reference_hits.size(),
                               o.ideal_differs ? 1u : 0u, o.ideal_reference_indices.size()};
    put(header, sizeof(header));
    put(o.reference_indices.data(), o.reference_indices.size() * 4);
    put(o.outside_keys.data(), o.outside_keys.size() * 8);
    put(o.plain_reference_indices.data(), o.plain_reference_indices.size() * 4);
    put(o.reference_hits.data(), o.reference_hits.size() * 2);
    put(o.ideal_reference_indices.data(), o.ideal_reference_indices.size() * 4);
  }
  return bytes;
}

void Decode(const std::string& bytes, std::span<Observation> observations) {
  size_t at = 0;
  const auto get = [&](void* p, size_t n) {
    VANTAGE_CHECK(at + n <= bytes.size());
    if (n) std::memcpy(p, bytes.data() + at, n);
    at += n;
  };
  for (Observation& o : observations) {
    uint64_t header[9];
    get(header, sizeof(header));
    o.reference_indices.resize(header[0]);
    o.outside_keys.resize(header[1]);
    o.plain_reference_indices.resize(header[2]);
    o.rays_traced = header[3];
    o.target_pixels = header[4];
    o.quality_pixels = header[5];
    o.reference_hits.resize(header[6]);
    get(o.reference_indices.data(), header[0] * 4);
    get(o.outside_keys.data(), header[1] * 8);
    get(o.plain_reference_indices.data(), header[2] * 4);
    get(o.reference_hits.data(), header[6] * 2);
    o.ideal_differs = header[7] != 0;  // the physical sensor model (issue 43)
    o.ideal_reference_indices.resize(header[8]);
    get(o.ideal_reference_indices.data(), header[8] * 4);
  }
  VANTAGE_CHECK(at == bytes.size());
}

// Bytes each rank sends per MPI_Gatherv round: its counts and displacements are ints, so one
// round's total must stay below INT_MAX. VANTAGE_MPI_CHUNK_BYTES lowers it (tests).
size_t ChunkBytes(int size) {
  size_t chunk = size_t{256} << 20;
  if (const char* value = std::getenv("VANTAGE_MPI_CHUNK_BYTES"))
    chunk = std::max<size_t>(1, std::strtoull(value, nullptr, 10));
  return std::max<size_t>(1, std::min(chunk, static_cast<size_t>(INT_MAX) / size));
}

// Every rank's bytes to rank 0, in rounds of at most ChunkBytes each; rank 0 gets them by rank.
std::vector<std::string> GatherBytes(const std::string& mine, int rank, int size,
                                     size_t* rounds) {
  std::vector<uint64_t> sizes(static_cast<size_t>(size));
  const uint64_t my_size = mine.size();
  MPI_Request request;
  MPI_Iallgather(&my_size, 1, MPI_UINT64_T, sizes.data(), 1, MPI_UINT64_T, MPI_COMM_WORLD,
                 &request);
  Wait(&request);
  const uint64_t largest = *std::max_element(sizes.begin(), sizes.end());
  const size_t chunk = ChunkBytes(size);
  std::vector<std::string> parts(rank == 0 ? static_cast<size_t>(size) : 0);
  std::vector<int> counts(static_cast<size_t>(size)), displacements(static_cast<size_t>(size));
  std::string buffer;
  *rounds = 0;
  for (uint64_t offset = 0; offset < largest; offset += chunk, ++*rounds) {
    const auto piece = [&](uint64_t total) {
      return static_cast<int>(total > offset ? std::min<uint64_t>(chunk, total - offset) : 0);
    };
    int total = 0;
    for (int r = 0; r < size; ++r) {
      counts[static_cast<size_t>(r)] = piece(sizes[static_cast<size_t>(r)]);
      displacements[static_cast<size_t>(r)] = total;
      total += counts[static_cast<size_t>(r)];
    }
    if (rank == 0) buffer.resize(static_cast<size_t>(total));
    const int send = piece(my_size);
    MPI_Igatherv(mine.data() + (send > 0 ? offset : 0), send, MPI_BYTE, buffer.data(),
                 counts.data(), displacements.data(), MPI_BYTE, 0, MPI_COMM_WORLD, &request);
    Wait(&request);
    if (rank != 0) continue;
    for (int r = 0; r < size; ++r)
      parts[static_cast<size_t>(r)].append(buffer, static_cast<size_t>(displacements[r]),
                                           static_cast<size_t>(counts[r]));
  }
  return parts;
}

// Rank 0's `bytes` to every rank (the others' `bytes` already have the size), in rounds below
// INT_MAX bytes: MPI's counts are ints.
void BroadcastBytes(std::string* bytes) {
  constexpr size_t kRound = size_t{1} << 30;
  for (size_t offset = 0; offset < bytes->size(); offset += kRound) {
    const int count = static_cast<int>(std::min(kRound, bytes->size() - offset));
    MPI_Request request;
    MPI_Ibcast(bytes->data() + offset, count, MPI_BYTE, 0, MPI_COMM_WORLD, &request);
    Wait(&request);
  }
}

// TraceCosts of every candidate, each rank estimating a slice (by count) and all of them
// gathering all: the estimate projects R's blocks as tracing does, so done in full on every rank
// it would cost each rank a tenth of a whole observe.
std::vector<uint64_t> SharedCosts(const Reference& reference, std::span<const Candidate> candidates,
                                  const ObserveOptions& options, int rank, int size) {
  VANTAGE_CHECK(candidates.size() <= static_cast<size_t>(INT_MAX));
  const auto slice_start = [&](int r) {
    return candidates.size() * static_cast<size_t>(r) / static_cast<size_t>(size);
  };
  std::vector<int> counts(static_cast<size_t>(size)), displacements(static_cast<size_t>(size));
  for (int r = 0; r < size; ++r) {
    displacements[static_cast<size_t>(r)] = static_cast<int>(slice_start(r));
    counts[static_cast<size_t>(r)] = static_cast<int>(slice_start(r + 1) - slice_start(r));
  }
  const size_t begin = slice_start(rank);
  const std::vector<uint64_t> mine =
      TraceCosts(reference, candidates.subspan(begin, slice_start(rank + 1) - begin), options);
  std::vector<uint64_t> all(candidates.size());
  MPI_Request request;
  MPI_Iallgatherv(mine.data(), static_cast<int>(mine.size()), MPI_UINT64_T, all.data(),
                  counts.data(), displacements.data(), MPI_UINT64_T, MPI_COMM_WORLD, &request);
  Wait(&request);
  return all;
}

}  // namespace

std::unique_ptr<MpiJob> MpiJob::Start(int* argc, char*** argv) {
  if (!LaunchedByMpi()) return nullptr;
  int provided = 0;
  // Only the main thread calls MPI; TBB's workers never do.
  MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided);
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  std::unique_ptr<MpiJob> job(new MpiJob(rank, size));
  g_job = job.get();
  // One report of the run: rank 0's log; the others say only errors.
  if (rank != 0) spdlog::set_level(spdlog::level::err);
  return job;
}

MpiJob::~MpiJob() {
  g_job = nullptr;
  MPI_Finalize();
}

void MpiJob::AgreeOnSettings(const RunSettings& settings) {
  const std::string build = BuildIdentity();
  const std::string text = JoinSettings(settings);
  Vote vote;
  vote.phase = kPhaseStart;
  vote.first = HashText(text);
  vote.second = HashText(build);
  const std::vector<Vote> votes = Agree(vote, size_);
  const auto stop = [this](int code, const std::string& message) {
    MpiJobAccess::Stop(this);
    return JobStopped(code, rank_ == 0 ? message : std::string());
  };
  for (int r = 0; r < size_; ++r) {
    const Vote& v = votes[static_cast<size_t>(r)];
    if (v.code != 0) throw stop(static_cast<int>(AgreedCode(votes)), "");  // it reports itself
    if (v.phase != kPhaseStart)  // done already: `vantage help`, --version
      throw stop(2, fmt::format("rank {} of {} ran another command than rank 0 — give every rank "
                                "the same command, files and options",
                                r, size_));
  }
  for (int r = 1; r < size_; ++r) {
    if (votes[static_cast<size_t>(r)].second != votes[0].second)
      throw stop(2, fmt::format("rank {} of {} runs another vantage build than rank 0 ({}) — "
                                "run one build on every rank",
                                r, size_, build));
  }
  const auto differs = std::find_if(votes.begin() + 1, votes.end(), [&](const Vote& v) {
    return v.first != votes[0].first;
  });
  if (differs == votes.end()) return;
  // Rank 0 names the option: every rank sends its settings (all of them take part, as all saw
  // the same votes).
  size_t rounds = 0;
  const std::vector<std::string> all = GatherBytes(text, rank_, size_, &rounds);
  const int r = static_cast<int>(differs - votes.begin());
  std::string difference;
  if (rank_ == 0)
    difference = SettingsDifference(SplitSettings(all[static_cast<size_t>(r)]),
                                    fmt::format("rank {}", r), settings, "rank 0");
  throw stop(2, fmt::format("rank {} of {} was given other options than rank 0: {} — give every "
                            "rank the same command, files and options",
                            r, size_, difference));
}

TraceFunction MpiJob::Tracer() {
  return [this](const RayScene& rays, const Reference& reference,
                std::span<const Candidate> candidates, const ObserveOptions& options) {
    const auto stop = [this](int code, const std::string& message) {
      MpiJobAccess::Stop(this);
      return JobStopped(code, message);
    };
    // Rank 0 alone words a refusal: every rank sees the same votes and stops alike.
    const auto said = [this](const std::string& message) {
      return rank_ == 0 ? message : std::string();
    };
    Vote entry;
    entry.phase = kPhaseTrace;
    entry.first = rays.GeometryFingerprint();
    entry.second = InputFingerprint(reference, candidates, options);
    const std::vector<Vote> before = Agree(entry, size_);
    for (int r = 0; r < size_; ++r) {
      const Vote& v = before[static_cast<size_t>(r)];
      if (v.code != 0) throw stop(static_cast<int>(AgreedCode(before)), "");
      // The settings agreed, so a rank that is done while rank 0 traces had fewer geometries to
      // trace: another scene (fewer states).
      if (v.phase == kPhaseFinish)
        throw stop(2, said(fmt::format("rank {} of {} ended while rank 0 traced: its scene has "
                                       "other states — give every rank the same files",
                                       r, size_)));
      if (v.phase != kPhaseTrace)
        throw stop(1, said(fmt::format("rank {} of {} ended while the others traced", r, size_)));
    }
    for (int r = 1; r < size_; ++r) {
      const Vote& v = before[static_cast<size_t>(r)];
      if (v.first != before[0].first)
        throw stop(2, said(fmt::format(
                          "rank {} of {} traces another scene geometry than rank 0: its scene, "
                          "or a file the scene includes (a mesh, a URDF, an included model), "
                          "differs — give every rank the same files",
                          r, size_)));
      if (v.second != before[0].second)
        throw stop(2, said(fmt::format("rank {} of {} has other candidates, R or observe options "
                                       "than rank 0 — give every rank the same command, files "
                                       "and options",
                                       r, size_)));
    }
    const auto split_start = std::chrono::steady_clock::now();
    const std::vector<uint64_t> costs = SharedCosts(reference, candidates, options, rank_, size_);
    const std::vector<size_t> bounds = SplitByCost(costs, static_cast<size_t>(size_));
    if (rank_ == 0) {
      uint64_t total = 0, largest = 0;
      for (uint64_t c : costs) total += c;
      for (int r = 0; r < size_; ++r) {
        uint64_t share = 0;
        for (size_t i = bounds[static_cast<size_t>(r)]; i < bounds[static_cast<size_t>(r) + 1]; ++i)
          share += costs[i];
        largest = std::max(largest, share);
      }
      spdlog::info("split: {} candidates over {} ranks by estimated rays in {:.3f} s, the largest "
                   "share {:.1f} % of them",
                   candidates.size(), size_,
                   std::chrono::duration<double>(std::chrono::steady_clock::now() - split_start)
                       .count(),
                   total ? 100.0 * double(largest) / double(total) : 0.0);
    }
    const size_t begin = bounds[static_cast<size_t>(rank_)];
    const size_t end = bounds[static_cast<size_t>(rank_) + 1];
    Vote traced;
    traced.phase = kPhaseTraced;
    std::string message, bytes;
    try {
      bytes = Encode(Observe(rays, reference, candidates.subspan(begin, end - begin), options));
    } catch (const InputError& e) {
      traced.code = 2;
      message = e.what();
    } catch (const std::exception& e) {
      traced.code = 1;
      message = fmt::format("internal error: {}", e.what());
    }
    // A rank killed here, for the test of a job that loses a rank (docs/distributed.md).
    if (EnvInt("VANTAGE_TEST_KILL_RANK", -1) == rank_) std::raise(SIGKILL);
    traced.message_hash = HashText(message);
    const std::vector<Vote> after = Agree(traced, size_);
    if (AgreedCode(after) != 0)
      throw stop(static_cast<int>(AgreedCode(after)), Attribution(after, rank_, message));
    spdlog::debug("rank {} of {}: traced candidates {} to {} of {}", rank_, size_, begin, end,
                  candidates.size());
    const auto gather_start = std::chrono::steady_clock::now();
    size_t rounds = 0;
    const std::vector<std::string> parts = GatherBytes(bytes, rank_, size_, &rounds);
    std::vector<Observation> all(candidates.size());
    uint64_t gathered = 0;
    for (size_t r = 0; r < parts.size(); ++r) {
      Decode(parts[r], std::span<Observation>(all).subspan(bounds[r], bounds[r + 1] - bounds[r]));
      gathered += parts[r].size();
    }
    if (rank_ == 0) {
      const double seconds =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - gather_start).count();
      spdlog::info(
          "gather: {} sets from {} ranks, {:.2f} MiB ({:.0f} bytes per set), {} rounds, {:.3f} s",
          candidates.size(), size_, gathered / 1048576.0,
          candidates.empty() ? 0.0 : double(gathered) / double(candidates.size()), rounds,
          seconds);
    }
    return all;
  };
}

TraceFunction MpiJob::BroadcastTracer() {
  return [this](const RayScene& rays, const Reference& reference,
                std::span<const Candidate> candidates, const ObserveOptions& options) {
    VANTAGE_CHECK(rank_ == 0);
    // The poses travel as a visibility file's candidates (its encoder checks and versions them);
    // R follows from the scene every rank has, and Tracer's fingerprint confirms it.
    VisibilityFile poses;
    poses.reference.cell_size = reference.cell_size;
    poses.candidates.assign(candidates.begin(), candidates.end());
    poses.observations.resize(candidates.size());
    std::string bytes = EncodeVisibility(poses);
    Vote ask;
    ask.phase = kPhaseRefine;
    ask.first = bytes.size();
    const std::vector<Vote> votes = Agree(ask, size_);
    for (int r = 1; r < size_; ++r) {
      if (votes[static_cast<size_t>(r)].phase != kPhaseServe) {
        MpiJobAccess::Stop(this);
        throw JobStopped(1, fmt::format("rank {} of {} was not waiting for refinement's poses",
                                        r, size_));
      }
    }
    BroadcastBytes(&bytes);
    return Tracer()(rays, reference, candidates, options);
  };
}

void MpiJob::ServeTraces(const RayScene& rays, const Reference& reference,
                         const ObserveOptions& options) {
  VANTAGE_CHECK(rank_ != 0);
  const TraceFunction trace = Tracer();
  while (true) {
    Vote wait;
    wait.phase = kPhaseServe;
    const std::vector<Vote> votes = Agree(wait, size_);
    if (votes[0].phase != kPhaseRefine) {
      // Rank 0's Finish (or its failure): this was the job's last agreement.
      served_finish_.resize(votes.size() * kVoteWords);
      std::memcpy(served_finish_.data(), votes.data(), served_finish_.size() * 8);
      return;
    }
    std::string bytes(votes[0].first, '\0');
    BroadcastBytes(&bytes);
    const VisibilityFile poses = DecodeVisibility(bytes, "rank 0's refined poses");
    trace(rays, reference, poses.candidates, options);
  }
}

int MpiJob::Finish(int code, const std::string& message, std::string* print) {
  Vote last;
  last.code = static_cast<uint64_t>(code);
  last.message_hash = HashText(message);
  last.phase = kPhaseFinish;
  std::vector<Vote> votes;
  if (served_finish_.empty()) {
    votes = Agree(last, size_);
  } else {
    // ServeTraces took part in rank 0's Finish already: the others decided on what it said then
    // (nothing had failed here); a failure since is this rank's own exit code.
    votes.resize(served_finish_.size() / kVoteWords);
    std::memcpy(static_cast<void*>(votes.data()), served_finish_.data(),
                served_finish_.size() * 8);
    votes[static_cast<size_t>(rank_)] = last;
  }
  stopped_ = true;
  *print = Attribution(votes, rank_, message);
  uint64_t agreed = AgreedCode(votes);
  const bool together = std::all_of(votes.begin(), votes.end(), [](const Vote& v) {
    return v.phase == kPhaseFinish || v.phase == kPhaseServe;
  });
  if (agreed == 0 && !together) agreed = 1;  // a rank still traced: the run is incomplete
  return static_cast<int>(agreed);
}

#endif  // VANTAGE_HAVE_MPI

}  // namespace vantage
