#include "crowd/formats/file_read.h"

#include <cerrno>
#include <cstring>
#include <fstream>

#include <sys/stat.h>

#include "crowd/formats/error.h"

namespace crowd {
namespace {

std::string mib(uint64_t bytes) { return std::to_string(bytes >> 20) + " MiB"; }

} // namespace

uint64_t checkRegularFile(const std::string &path, const FileBound &bound,
                          const std::string &label) {
  const std::string name = label.empty() ? path : label;
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0)
    throw Error(name + ": cannot open file (" + std::strerror(errno) + ")");
  if (!S_ISREG(st.st_mode))
    throw Error(name + ": not a regular file (" +
                (S_ISDIR(st.st_mode)                          ? "a folder"
                 : S_ISFIFO(st.st_mode)                       ? "a FIFO"
                 : S_ISCHR(st.st_mode) || S_ISBLK(st.st_mode) ? "a device"
                                                              : "not a plain file") +
                "): nothing read");
  if (uint64_t(st.st_size) > bound.maxBytes)
    throw Error(name + ": " + mib(uint64_t(st.st_size)) + " is over the input bound of " +
                mib(bound.maxBytes) + (bound.raise.empty() ? "" : " (" + bound.raise + ")") +
                ": nothing read");
  return uint64_t(st.st_size);
}

std::vector<uint8_t> readRegularFile(const std::string &path, const FileBound &bound,
                                     const std::string &label) {
  const uint64_t size = checkRegularFile(path, bound, label);
  const std::string name = label.empty() ? path : label;
  std::ifstream f(path, std::ios::binary);
  if (!f)
    throw Error(name + ": cannot open file");
  std::vector<uint8_t> bytes(size);
  f.read(reinterpret_cast<char *>(bytes.data()), std::streamsize(size));
  if (uint64_t(f.gcount()) != size)
    throw Error(name + ": changed while being read");
  return bytes;
}

} // namespace crowd
