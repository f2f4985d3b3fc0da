// The CBC child's answer as bytes (cbc_answer.hpp).
#include "select/cbc_answer.hpp"

#include <fmt/format.h>

#include <cstdint>
#include <cstring>

#include "select/child_process.hpp"
#include "vantage/error.hpp"

namespace vantage::detail {
namespace {

template <typename T>
void Append(std::string* bytes, const T& value) {
  bytes->append(reinterpret_cast<const char*>(&value), sizeof(T));
}

template <typename T>
T Take(const std::string& bytes, size_t* offset) {
  T value;
  VANTAGE_CHECK(*offset + sizeof(T) <= bytes.size());
  std::memcpy(&value, bytes.data() + *offset, sizeof(T));
  *offset += sizeof(T);
  return value;
}

}  // namespace

std::string EncodeAnswer(CbcModelHandle* cbc, int x_count) {
  const CbcModuleApi& api = Cbc();
  std::string bytes;
  Append(&bytes, api.cbc_best_possible_obj_value(cbc));
  Append(&bytes, static_cast<int32_t>(api.cbc_is_proven_optimal(cbc) != 0));
  Append(&bytes, static_cast<int32_t>(api.cbc_status(cbc)));
  Append(&bytes, static_cast<int32_t>(api.cbc_secondary_status(cbc)));
  const double* solution = api.cbc_best_solution(cbc);
  std::vector<int32_t> chosen;
  for (int q = 0; solution != nullptr && q < x_count; ++q)
    if (solution[q] > 0.5) chosen.push_back(q);
  Append(&bytes, static_cast<int32_t>(solution != nullptr));
  Append(&bytes, static_cast<int32_t>(chosen.size()));
  for (const int32_t q : chosen) Append(&bytes, q);
  return bytes;
}

CbcAnswer DecodeAnswer(const std::string& bytes, int x_count) {
  CbcAnswer answer;
  size_t offset = 0;
  answer.bound = Take<double>(bytes, &offset);
  answer.proven_optimal = Take<int32_t>(bytes, &offset) != 0;
  answer.status = Take<int32_t>(bytes, &offset);
  answer.secondary_status = Take<int32_t>(bytes, &offset);
  answer.has_solution = Take<int32_t>(bytes, &offset) != 0;
  const int32_t count = Take<int32_t>(bytes, &offset);
  VANTAGE_CHECK(count >= 0 && count <= x_count);
  for (int32_t i = 0; i < count; ++i) {
    answer.chosen_columns.push_back(Take<int32_t>(bytes, &offset));
    VANTAGE_CHECK(answer.chosen_columns.back() >= 0 && answer.chosen_columns.back() < x_count);
  }
  VANTAGE_CHECK(offset == bytes.size());
  return answer;
}

std::string StatusInWords(const CbcAnswer& answer) {
  switch (answer.secondary_status) {
    case 2:
      return "stopped at its allowed gap";
    case 3:
      return "stopped at its node limit";
    case 4:
      return "reached the time limit — raise --time-limit to prove more";
    case 5:
      return "was stopped by a signal";
    case 6:
      return "stopped at its solution limit";
    case 8:
      return "stopped at its iteration limit";
    default:
      return fmt::format("stopped (status {}, secondary status {})", answer.status,
                         answer.secondary_status);
  }
}

std::optional<CbcAnswer> SolveInChild(CbcModelHandle* cbc, int x_count, double seconds,
                                      std::string* note) {
  std::string why;
  const std::optional<std::string> bytes = RunInChildProcess(
      [&] {
        Cbc().cbc_solve(cbc);
        return EncodeAnswer(cbc, x_count);
      },
      seconds, &why);
  if (!bytes) {
    *note = fmt::format("CBC {} — raise --time-limit to let it finish", why);
    return std::nullopt;
  }
  return DecodeAnswer(*bytes, x_count);
}

}  // namespace vantage::detail
