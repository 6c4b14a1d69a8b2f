// Untrusted input files: where a file named by another file (a glTF's buffer or image URI, a
// manifest's body or outfit) may resolve, and how any input is read. A named path resolves only
// inside its root: the naming file's own folder, or the --asset-root the user gives. `..` that
// leaves the root, absolute paths outside a given --asset-root (without one, every absolute
// path), symlinks resolving outside it, and anything that is not a
// regular file (devices, FIFOs, directories) are errors naming the path. Every file's size is
// checked against a bound before a byte is read; hashing streams in fixed blocks.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "crowd/formats/file_read.h"
#include "crowd/formats/limits.h"

namespace crowd {

struct InputPolicy {
  // Where named files may resolve. Empty: the folder of the file that names them.
  std::string assetRoot;
  // Largest input file read, in bytes (--max-file-size).
  uint64_t maxFileBytes = limits::kInputFileBytes;
  void validate() const;
  // The bound a file read under this policy is checked against.
  FileBound bound() const { return {maxFileBytes, "--max-file-size raises it"}; }
};

// The path `name` (as written in `namingFile`, relative to its folder) resolves to, after the
// checks above; `what` says what named it ("buffer 0 URI"), for the error.
std::string resolveNamedInput(const std::string &name, const std::string &namingFile,
                              const InputPolicy &policy, const std::string &what);

// Size of `path` after checking it is a regular file within the policy's byte bound.
uint64_t checkInputFile(const std::string &path, const InputPolicy &policy);

// The whole of `path`, checked first as above; as text.
std::vector<uint8_t> readInputFile(const std::string &path, const InputPolicy &policy);
std::string readInputText(const std::string &path, const InputPolicy &policy);

// "sha256:HEX" and size of a file, read in 1 MiB blocks (never whole into memory); the file
// must be a regular file.
struct FileHash {
  std::string hash;
  uint64_t size = 0;
};
FileHash hashFile(const std::string &path);
std::string sha256Hex(const std::string &bytes);

} // namespace crowd
