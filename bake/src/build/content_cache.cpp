#include "crowd/bake/content_cache.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>

#include "crowd/bake/provenance.h"
#include "crowd/formats/container.h"
#include "crowd/formats/error.h"

namespace crowd {

namespace {

std::vector<uint8_t> readFile(const std::string &path) {
  std::ifstream f(path, std::ios::binary);
  if (!f)
    return {};
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

} // namespace

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
    Part part = partFromBytes(readFile(path), path);
    touch(key);
    return part;
  } catch (const std::exception &e) {
    problem = e.what();
    return std::nullopt;
  }
}

namespace {
void createParent(const std::string &folder, const std::string &path) {
  std::error_code ec;
  std::filesystem::create_directories(std::filesystem::path(path).parent_path(), ec);
  if (ec)
    throw Error(folder + ": cannot create cache folder: " + ec.message());
}
} // namespace

void ContentCache::touch(const std::string &key) const {
  std::error_code ec;
  std::filesystem::last_write_time(entryPath(key), std::filesystem::file_time_type::clock::now(),
                                   ec); // a cache on a read-only share is used as it is
}

void ContentCache::store(const std::string &key, const Part &part, const std::string &kind) const {
  const std::string path = entryPath(key);
  createParent(folder_, path);
  pack::writeFileAtomic(path, partBytes(part));
  nlohmann::ordered_json withKind = part.figures;
  withKind["job_kind"] = kind;
  const std::string figures = withKind.dump();
  pack::writeFileAtomic(path + ".figs", std::vector<uint8_t>(figures.begin(), figures.end()));
}

std::optional<nlohmann::ordered_json> ContentCache::loadFigures(const std::string &key) const {
  const auto bytes = readFile(entryPath(key) + ".figs");
  if (!bytes.empty()) {
    auto j = nlohmann::ordered_json::parse(bytes.begin(), bytes.end(), nullptr, false);
    if (j.is_object() && std::filesystem::exists(entryPath(key))) {
      j.erase("job_kind");
      touch(key);
      return j;
    }
  }
  std::string problem;
  if (auto part = load(key, problem))
    return part->figures;
  return std::nullopt;
}

void ContentCache::recordFailure(const std::string &key, const std::string &error) const {
  const std::string path = entryPath(key) + ".failed";
  createParent(folder_, path);
  pack::writeFileAtomic(path, std::vector<uint8_t>(error.begin(), error.end()));
}

void ContentCache::recordPack(const std::string &key, const std::string &hash) const {
  const std::string path = entryPath(key) + ".pack";
  createParent(folder_, path);
  pack::writeFileAtomic(path, std::vector<uint8_t>(hash.begin(), hash.end()));
}

std::optional<std::string> ContentCache::recordedPack(const std::string &key) const {
  const auto bytes = readFile(entryPath(key) + ".pack");
  if (bytes.empty())
    return std::nullopt;
  touch(key);
  return std::string(bytes.begin(), bytes.end());
}

std::optional<std::string> ContentCache::recordedFailure(const std::string &key) const {
  const auto bytes = readFile(entryPath(key) + ".failed");
  if (bytes.empty())
    return std::nullopt;
  return std::string(bytes.begin(), bytes.end());
}

void ContentCache::removeTemporaries(const std::string &key, long pid) const {
  namespace fs = std::filesystem;
  const fs::path entry = entryPath(key);
  const std::string mark = ".tmp-" + std::to_string(pid) + "-"; // pack::writeFileAtomic's names
  std::error_code ec;
  for (const auto &f : fs::directory_iterator(entry.parent_path(), ec)) {
    const std::string name = f.path().filename().string();
    if (name.rfind(entry.filename().string(), 0) == 0 && name.find(mark) != std::string::npos)
      fs::remove(f.path(), ec);
  }
}

} // namespace crowd
