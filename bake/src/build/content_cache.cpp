#include "crowd/bake/content_cache.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>

#include <openssl/evp.h>

#include "crowd/bake/provenance.h"
#include "crowd/formats/container.h"
#include "crowd/formats/error.h"

namespace crowd {

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

std::vector<uint8_t> readFile(const std::string &path) {
  std::ifstream f(path, std::ios::binary);
  if (!f)
    return {};
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

} // namespace

std::string sha256Hex(const std::string &bytes) {
  Sha256 h;
  h.add(bytes.data(), bytes.size());
  return h.hex();
}

FileHash hashFile(const std::string &path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
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

void keyJobs(std::vector<Job> &jobs) {
  std::map<std::string, FileHash> fileHashes;
  for (auto &job : jobs) {
    std::string text = std::string(kBakerVersion) + "\n" + job.kind + "\n" + job.settings.dump();
    job.hashes.clear();
    for (const auto &f : job.files) {
      auto [it, fresh] = fileHashes.try_emplace(f);
      if (fresh)
        it->second = hashFile(f);
      job.hashes.push_back(it->second);
      text += "\nfile " + it->second.hash; // content only: the same bytes elsewhere hit the cache
    }
    for (size_t d : job.deps)
      text += "\ndep " + jobs.at(d).key;
    job.key = sha256Hex(text);
  }
}

std::string ContentCache::entryPath(const std::string &key) const {
  return folder_ + "/" + key.substr(0, 2) + "/" + key + ".part";
}

std::optional<Part> ContentCache::load(const std::string &key, std::string &problem) const {
  const std::string path = entryPath(key);
  std::error_code ec;
  if (!std::filesystem::exists(path, ec))
    return std::nullopt;
  try {
    return partFromBytes(readFile(path), path);
  } catch (const std::exception &e) {
    problem = e.what();
    return std::nullopt;
  }
}

void ContentCache::store(const std::string &key, const Part &part) const {
  const std::string path = entryPath(key);
  std::error_code ec;
  std::filesystem::create_directories(std::filesystem::path(path).parent_path(), ec);
  if (ec)
    throw Error(folder_ + ": cannot create cache folder: " + ec.message());
  pack::writeFileAtomic(path, partBytes(part));
}

} // namespace crowd
