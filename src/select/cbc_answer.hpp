#pragma once
/// What a CBC run in the child process (child_process.hpp) reports back to the parent: its
/// bound, status and the x columns at 1, as bytes. The selection MILP (milp.hpp) solves in a child
/// and reads the answer this way.
#include <algorithm>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "select/cbc_module.hpp"

namespace vantage::detail {

/// How every exact model shares its time limit with CBC: CBC's search gets kCbcTimeShare of it,
/// and its child is killed at kCbcKillShare when CBC has not noticed (its root LP ignores it).
inline constexpr double kCbcTimeShare = 0.85;
inline constexpr double kCbcKillShare = 0.9;

/// The largest model (constraint nonzeros) CBC is handed for `time_limit` seconds. CBC checks
/// its limit only between steps and the root LP alone runs to the end, about 5-15 µs per nonzero
/// (exact.cpp measured 1.3 M nonzeros: 20 s), so larger models are not attempted; the floor keeps
/// tiny limits usable.
inline double CbcMaxNonzeros(double time_limit) { return std::max(20000.0, 40000.0 * time_limit); }

struct CbcModelDeleter {
  void operator()(CbcModelHandle* model) const { Cbc().cbc_delete_model(model); }
};
using CbcModelPtr = std::unique_ptr<CbcModelHandle, CbcModelDeleter>;

struct CbcAnswer {
  double bound = std::numeric_limits<double>::quiet_NaN();  ///< CBC's best possible objective
  bool has_solution = false;
  bool proven_optimal = false;
  int status = 0;
  int secondary_status = 0;
  std::vector<int> chosen_columns;  ///< of the first x_count columns, those at 1 (ascending)
};

/// The answer of the solved `cbc` (in the child), its first `x_count` columns being the x's.
std::string EncodeAnswer(CbcModelHandle* cbc, int x_count);
/// EncodeAnswer's bytes back (in the parent); VANTAGE_CHECKs that they are well formed.
CbcAnswer DecodeAnswer(const std::string& bytes, int x_count);
/// Solves `cbc` in a child process (child_process.hpp: its root LP ignores the time limit and its
/// SIGINT handler swallows Ctrl-C, a child can be stopped) for at most `seconds`, and reads its
/// answer back. Nullopt when the child was stopped or failed, with `note` saying so.
std::optional<CbcAnswer> SolveInChild(CbcModelHandle* cbc, int x_count, double seconds,
                                      std::string* note);
/// CBC's secondary status in words (CbcModel::secondaryStatus), with what the user can change.
std::string StatusInWords(const CbcAnswer& answer);

}  // namespace vantage::detail
