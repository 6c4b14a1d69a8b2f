#include "crowd/bake/input_files.h"

#include <cstdio>
#include <filesystem>
#include <fstream>

#include <openssl/evp.h>

#include "crowd/formats/error.h"
#include "crowd/formats/file_read.h"

namespace crowd {

namespace fs = std::filesystem;

namespace {

// SHA-256 through OpenSSL's EVP interface, fed in pieces.
class Sha256 {
public:
  Sha256() : ctx_(EVP_MD_CTX_new()) {
    if (!ctx_ || EVP_DigestInit_ex(ctx_, EVP_sha256(), nullptr) != 1)
      throw Error("sha256: cannot initialise OpenSSL's digest");
  }
  ~Sha256() { EVP_MD_CTX_free(ctx_); }
  Sha256(const Sha256 &) = delete;
  Sha256 &operator=(const Sha256 &) = delete;
  void add(const void *data, size_t size) { EVP_DigestUpdate(ctx_, data, size); }
  std::string hex() {
    unsigned char digest[EVP_MAX_MD_SIZE];
    unsigned int n = 0;
    EVP_DigestFinal_ex(ctx_, digest, &n);
    std::string out;
    char b[3];
    for (unsigned i = 0; i < n; ++i) {
      std::snprintf(b, sizeof b, "%02x", digest[i]);
      out += b;
    }
    return out;
  }

private:
  EVP_MD_CTX *ctx_;
};

// True when `p` (absolute, normalised) is `root` or lies below it.
bool inside(const fs::path &p, const fs::path &root) {
  const fs::path rel = p.lexically_relative(root);
  return !rel.empty() && *rel.begin() != "..";
}

} // namespace

void InputPolicy::validate() const {
  if (maxFileBytes == 0)
    throw Error("max-file-size: must be at least 1 byte");
  std::error_code ec;
  if (!assetRoot.empty() && !fs::is_directory(assetRoot, ec))
    throw Error("asset-root: " + assetRoot + " is not a folder");
}

std::string resolveNamedInput(const std::string &name, const std::string &namingFile,
                              const InputPolicy &policy, const std::string &what) {
  const std::string ctx = namingFile + ": " + what + " '" + name + "'";
  const std::string widen = " (pass --asset-root DIR to allow a wider folder)";
  if (name.empty())
    throw Error(ctx + ": empty path");
  if (name.find('\0') != std::string::npos)
    throw Error(ctx + ": contains a NUL byte");
  // An absolute path (a farm's manifest naming assets on a shared mount) only inside the root
  // the user gave: without one, the naming file's folder is no root for it.
  const bool absolute = fs::path(name).is_absolute();
  if (absolute && policy.assetRoot.empty())
    throw Error(ctx +
                ": an absolute path is allowed only inside --asset-root DIR; name files "
                "relative to " +
                namingFile + " or pass --asset-root");
  std::error_code ec;
  const fs::path parent = fs::path(namingFile).parent_path();
  const fs::path folder =
      fs::absolute(parent.empty() ? fs::path(".") : parent, ec).lexically_normal();
  const fs::path rootDir = policy.assetRoot.empty() ? folder : fs::absolute(policy.assetRoot, ec);
  const fs::path lexical = (folder / name).lexically_normal(); // `name` where it is absolute
  const fs::path root = rootDir.lexically_normal();
  if (!inside(lexical, root))
    throw Error(ctx + (absolute ? ": lies outside --asset-root " : ": leaves the asset folder ") +
                root.string() + (absolute ? "" : widen));
  // Symlinks are followed only where they stay inside the (also resolved) root.
  const fs::path real = fs::weakly_canonical(lexical, ec);
  const fs::path realRoot = fs::weakly_canonical(root, ec);
  if (ec || !inside(real, realRoot))
    throw Error(ctx + ": resolves through a link to " + real.string() +
                ", outside the asset folder " + realRoot.string() + widen);
  return lexical.string();
}

uint64_t checkInputFile(const std::string &path, const InputPolicy &policy) {
  return checkRegularFile(path, policy.bound());
}

std::vector<uint8_t> readInputFile(const std::string &path, const InputPolicy &policy) {
  return readRegularFile(path, policy.bound());
}

std::string readInputText(const std::string &path, const InputPolicy &policy) {
  const std::vector<uint8_t> bytes = readInputFile(path, policy);
  return std::string(bytes.begin(), bytes.end());
}

std::string sha256Hex(const std::string &bytes) {
  Sha256 h;
  h.add(bytes.data(), bytes.size());
  return h.hex();
}

FileHash hashFile(const std::string &path) {
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (!fs::exists(st))
    throw Error(path + ": no such file");
  if (!fs::is_regular_file(st))
    throw Error(path + ": not a regular file");
  std::ifstream f(path, std::ios::binary);
  if (!f)
    throw Error(path + ": cannot open file");
  Sha256 h;
  FileHash out;
  std::vector<char> block(1 << 20);
  while (f) {
    f.read(block.data(), std::streamsize(block.size()));
    const auto n = size_t(f.gcount());
    h.add(block.data(), n);
    out.size += n;
  }
  if (f.bad())
    throw Error(path + ": read error");
  out.hash = "sha256:" + h.hex();
  return out;
}

} // namespace crowd
