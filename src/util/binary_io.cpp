#include "util/binary_io.hpp"

#include <fmt/format.h>

#include "vantage/error.hpp"

namespace vantage::detail {

uint64_t Fnv1a64(std::string_view bytes) {
  uint64_t hash = 0xcbf29ce484222325ULL;
  for (unsigned char c : bytes) {
    hash ^= c;
    hash *= 0x100000001b3ULL;
  }
  return hash;
}

void BinaryReader::Read(void* out, size_t n) {
  if (n == 0) return;  // an empty vector's data() may be null: memcpy must not see it
  if (n > data_.size() - pos_)
    throw InputError(fmt::format("{}: truncated at byte {} (needs {} more bytes) — the file is corrupt",
                                 file_, pos_, n));
  std::memcpy(out, data_.data() + pos_, n);
  pos_ += n;
}

void BinaryReader::Skip(size_t n) {
  std::string scratch(n, '\0');
  Read(scratch.data(), n);
}

uint32_t BinaryReader::U32() {
  uint32_t v = 0;
  Read(&v, 4);
  return v;
}

uint64_t BinaryReader::U64() {
  uint64_t v = 0;
  Read(&v, 8);
  return v;
}

double BinaryReader::F64() {
  double v = 0;
  Read(&v, 8);
  return v;
}

void BinaryReader::CheckCount(uint64_t count, size_t min_item_bytes) const {
  if (count > (data_.size() - pos_) / std::max<size_t>(min_item_bytes, 1))
    throw InputError(fmt::format("{}: count {} at byte {} exceeds the file size — the file is corrupt",
                                 file_, count, pos_));
}

std::string BinaryReader::Str() {
  const uint64_t n = U64();
  CheckCount(n, 1);
  std::string s(n, '\0');
  Read(s.data(), n);
  return s;
}

template <typename T>
std::vector<T> BinaryReader::Vector() {
  const uint64_t n = U64();
  CheckCount(n, sizeof(T));
  std::vector<T> v(n);
  Read(v.data(), n * sizeof(T));
  return v;
}

std::vector<uint16_t> BinaryReader::U16Vector() { return Vector<uint16_t>(); }
std::vector<uint32_t> BinaryReader::U32Vector() { return Vector<uint32_t>(); }
std::vector<uint64_t> BinaryReader::U64Vector() { return Vector<uint64_t>(); }

}  // namespace vantage::detail
