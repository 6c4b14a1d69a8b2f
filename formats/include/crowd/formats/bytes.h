// Little-endian byte writer and a bounds-checked byte reader used by every chunk schema.
#pragma once
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

#include "crowd/formats/error.h"

namespace crowd::pack {

class ByteWriter {
public:
  template <class T> void put(T value) {
    static_assert(std::is_arithmetic_v<T>);
    size_t at = bytes_.size(); // resize + memcpy: vector::insert trips a GCC 12 false warning
    bytes_.resize(at + sizeof(T));
    std::memcpy(bytes_.data() + at, &value, sizeof(T)); // host is little-endian (container.cpp)
  }
  void putString(const std::string &s);
  template <class T> void putArray(const std::vector<T> &values) {
    static_assert(std::is_arithmetic_v<T>);
    put<uint64_t>(values.size());
    align(16);
    const auto *raw = reinterpret_cast<const uint8_t *>(values.data());
    bytes_.insert(bytes_.end(), raw, raw + values.size() * sizeof(T));
  }
  void align(size_t to);
  std::vector<uint8_t> take() { return std::move(bytes_); }

private:
  std::vector<uint8_t> bytes_;
};

// Every read is bounds-checked; a failure names the pack, chunk and field.
class ByteReader {
public:
  ByteReader(std::span<const uint8_t> bytes, std::string context)
      : bytes_(bytes), context_(std::move(context)) {}

  template <class T> T get(const char *field) {
    static_assert(std::is_arithmetic_v<T>);
    need(sizeof(T), field);
    T value;
    std::memcpy(&value, bytes_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
    return value;
  }
  std::string getString(const char *field);
  // Reads an array written by putArray; `maxCount` guards absurd sizes before allocating.
  template <class T> std::vector<T> getArray(const char *field, uint64_t maxCount = UINT32_MAX) {
    uint64_t count = get<uint64_t>(field);
    if (count > maxCount)
      fail(field, "count " + std::to_string(count) + " exceeds limit " + std::to_string(maxCount));
    align(16, field);
    if (count > (bytes_.size() - pos_) / sizeof(T))
      fail(field, "array of " + std::to_string(count) + " elements runs past the chunk end");
    std::vector<T> values(count);
    if (count)
      std::memcpy(values.data(), bytes_.data() + pos_, count * sizeof(T));
    pos_ += count * sizeof(T);
    return values;
  }
  void align(size_t to, const char *field);
  void expectEnd();
  [[noreturn]] void fail(const char *field, const std::string &what) const;
  const std::string &context() const { return context_; }

private:
  void need(size_t n, const char *field) const;
  std::span<const uint8_t> bytes_;
  size_t pos_ = 0;
  std::string context_;
};

} // namespace crowd::pack
