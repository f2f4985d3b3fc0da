#pragma once
/// Little-endian binary writer/reader for vantage's own files, with bounds checks on every read
/// so that a truncated or hostile file gives an InputError, never a crash or a huge allocation.
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

namespace vantage::detail {

uint64_t Fnv1a64(std::string_view bytes);

class BinaryWriter {
 public:
  void Bytes(const void* p, size_t n) { data_.append(static_cast<const char*>(p), n); }
  void U32(uint32_t v) { Bytes(&v, 4); }
  void U64(uint64_t v) { Bytes(&v, 8); }
  void F64(double v) { Bytes(&v, 8); }
  void Str(const std::string& s) {
    U64(s.size());
    Bytes(s.data(), s.size());
  }
  void U32Vector(const std::vector<uint32_t>& v) {
    U64(v.size());
    Bytes(v.data(), v.size() * 4);
  }
  void U16Vector(const std::vector<uint16_t>& v) {
    U64(v.size());
    Bytes(v.data(), v.size() * 2);
  }
  void U64Vector(const std::vector<uint64_t>& v) {
    U64(v.size());
    Bytes(v.data(), v.size() * 8);
  }
  const std::string& data() const { return data_; }

 private:
  std::string data_;
};

class BinaryReader {
 public:
  BinaryReader(std::string_view data, std::string file) : data_(data), file_(std::move(file)) {}
  void Skip(size_t n);
  uint32_t U32();
  uint64_t U64();
  double F64();
  std::string Str();
  std::vector<uint32_t> U32Vector();
  std::vector<uint64_t> U64Vector();
  std::vector<uint16_t> U16Vector();
  /// Throws unless `count` items of at least `min_item_bytes` each can still be read.
  void CheckCount(uint64_t count, size_t min_item_bytes) const;
  bool AtEnd() const { return pos_ == data_.size(); }

 private:
  void Read(void* out, size_t n);
  /// A u64 count, then that many little-endian values of T.
  template <typename T>
  std::vector<T> Vector();
  std::string_view data_;
  std::string file_;
  size_t pos_ = 0;
};

}  // namespace vantage::detail
