// The importer's accessor stage: a glTF accessor's elements as doubles, read as the glTF 2.0
// specification lays them out (byteStride, normalised integers, sparse substitution), every
// range checked against its buffer view and buffer before a byte is read.
#pragma once
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <tiny_gltf.h>

namespace crowd::gltf {

class Accessors {
public:
  // Errors name `path`; `stage` is set to what is being read (the importer's out-of-memory
  // message says it). `model` is read when asked, so it may be loaded after construction.
  Accessors(const tinygltf::Model &model, const std::string &path, std::string &stage)
      : model_(model), path_(path), stage_(stage) {}

  // Every element of accessor `index` as doubles (count * components), normalised per the
  // specification. The count is checked against the limits and the buffer view before anything
  // is allocated; `finite` refuses NaN and infinity. An accessor read again (several primitives
  // share it) is the same vector.
  std::shared_ptr<const std::vector<double>> read(int index, const std::string &what,
                                                  bool finite = true);
  // An accessor's declared count (not yet checked against its buffer view), and its type.
  size_t count(int index) const;
  int type(int index, const std::string &what) const;

private:
  [[noreturn]] void fail(const std::string &what) const;
  // Bytes of `count` elements of `elemSize` at `offset` with `stride` inside buffer view `view`.
  const uint8_t *viewRange(int view, size_t offset, size_t count, size_t stride, size_t elemSize,
                           const std::string &what) const;

  const tinygltf::Model &model_;
  const std::string &path_;
  std::string &stage_;
  std::map<std::pair<int, bool>, std::shared_ptr<const std::vector<double>>> cache_;
};

} // namespace crowd::gltf
