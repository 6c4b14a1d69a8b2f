// Compressed joint tracks against today's animation texture, in one run: per clip of each model
// given (default: ../shared/assets/gltf and tests/data's Blender, gltfpack and keyed exports), the
// bytes and the largest vertex error at any time measured (mm at 1.8 m) of both, the time each bake
// took, the CPU time of one pose decoded from each (every joint's matrix at a time), and ACL
// 2.1's bytes and compression time (`acl_compress_ms`, one compress_track_list call measured on
// this machine class) where ../shared/anchors/acl_animation_bytes.csv has the clip; per model,
// the tracks' compression time against the sum of ACL's, and the default bake's time (every
// store searched as `crowdbake anim` does) against it.
//   track_bench [--budget MM] [--csv OUT.csv] [--anchors CSV] [MODEL.glb ...]
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "crowd/bake/anim_bake.h"
#include "crowd/bake/import.h"
#include "crowd/bake/track_compression.h"
#include "crowd/formats/error.h"
#include "crowd/runtime/texture_skinning.h"
#include "crowd/runtime/track_pose.h"

namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

struct AclRow {
  long bytes = 0;
  double ms = 0; // acl_compress_ms
};

// ACL's fewest bytes measured within 1 mm and the time that compression took, by "model/clip".
std::map<std::string, AclRow> aclRows(const std::string &path) {
  std::map<std::string, AclRow> out;
  std::ifstream in(path);
  std::string line;
  std::getline(in, line); // header
  while (std::getline(in, line)) {
    if (line.find("fewest bytes") == std::string::npos)
      continue;
    std::vector<std::string> f;
    std::string cell;
    bool quoted = false;
    for (char ch : line) {
      if (ch == '"')
        quoted = !quoted;
      else if (ch == ',' && !quoted)
        f.push_back(cell), cell.clear();
      else
        cell += ch;
    }
    f.push_back(cell);
    if (f.size() > 13)
      out[f[0] + "/" + f[1]] = {std::stol(f[7]), std::stod(f[13])};
  }
  return out;
}

} // namespace

int main(int argc, char **argv) {
  double budget = 1.0;
  std::string csvPath,
      anchors = std::string(CROWD_SHARED_ASSETS) + "/../../anchors/acl_animation_bytes.csv";
  std::vector<std::string> models;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--budget" && i + 1 < argc)
      budget = std::stod(argv[++i]);
    else if (a == "--csv" && i + 1 < argc)
      csvPath = argv[++i];
    else if (a == "--anchors" && i + 1 < argc)
      anchors = argv[++i];
    else
      models.push_back(a);
  }
  if (models.empty())
    for (const std::string &dir :
         {std::string(CROWD_SHARED_ASSETS), std::string(CROWD_SOURCE_DIR) + "/tests/data/blender",
          std::string(CROWD_SOURCE_DIR) + "/tests/data/gltfpack"})
      if (std::filesystem::exists(dir))
        for (const auto &e : std::filesystem::recursive_directory_iterator(dir))
          if (e.path().extension() == ".glb" || e.path().extension() == ".gltf")
            models.push_back(e.path().string());
  std::sort(models.begin(), models.end());
  const auto acl = aclRows(anchors);

  std::ostringstream csv;
  csv << "model,clip,joints,keys,samples,default,constant,animated,mean_bits,tracks_bytes,"
         "tracks_max_mm,tracks_at_samples_mm,tracks_mids_mm,tracks_random_mm,tracks_s,"
         "tracks_pose_us,texture_bytes,texture_max_mm,texture_s,texture_pose_us,acl_bytes,"
         "acl_compress_ms\n";
  std::printf("%-28s %-14s %5s %5s %9s %8s %9s %8s %8s %6s %6s %7s %7s\n", "model", "clip", "keys",
              "samp", "tracks B", "err mm", "texture B", "err mm", "ACL B", "x ACL", "x tex",
              "pose us", "tex us");
  long totalTracks = 0, totalAcl = 0, totalTexture = 0, tracksWithAcl = 0, textureWithAcl = 0;
  double tracksSeconds = 0, textureSeconds = 0;
  for (const std::string &path : models) {
    const std::string model = std::filesystem::path(path).stem().string();
    crowd::Reporter reporter;
    reporter.quiet = true;
    crowd::Character c;
    try {
      c = crowd::importGltf(path, {}, reporter);
    } catch (const crowd::Error &e) {
      std::printf("%-28s skipped: %s\n", model.c_str(), e.what());
      continue;
    }
    if (c.clips.empty() || !c.skinned)
      continue;
    // Today's path: the error budget's choice of rate and precision, per clip.
    crowd::AnimBakeOptions options;
    options.errorBudgetMm = budget;
    options.store = "texture"; // the texture alone: the default (auto) also compresses tracks
    auto t0 = Clock::now();
    const crowd::AnimBakeResult baseline = crowd::bakeAnimation(c, options, reporter);
    const double textureTime = secondsSince(t0);
    textureSeconds += textureTime;
    uint64_t textureAll = 0;
    for (const auto &cb : baseline.budget.clips)
      for (const auto &o : cb.tried)
        if (o.precision == baseline.budget.precision && o.fps == cb.fps)
          textureAll += o.bytes;

    // The default bake (store auto: the texture searched, the tracks compressed, one kept).
    crowd::AnimBakeOptions defaults;
    defaults.errorBudgetMm = budget;
    t0 = Clock::now();
    crowd::bakeAnimation(c, defaults, reporter);
    const double defaultTime = secondsSince(t0);
    double modelTracksSeconds = 0, modelAclMs = 0;
    long modelTracks = 0, modelAcl = 0;

    crowd::TrackCompressionOptions to;
    to.errorBudgetMm = budget;
    to.mmPerUnit = crowd::millimetresPerUnit(c);
    const crowd::TrackRig rig = crowd::trackRig(c);
    for (size_t k = 0; k < c.clips.size(); ++k) {
      const auto &clip = c.clips[k];
      t0 = Clock::now();
      const crowd::CompressedClip cc = crowd::compressClip(c, rig, clip, k, to);
      const double trackTime = secondsSince(t0);
      tracksSeconds += trackTime;
      modelTracksSeconds += trackTime;
      const auto &f = cc.figures;
      uint64_t textureBytes = 0;
      double textureError = 0;
      const auto &cb = baseline.budget.clips[k];
      for (const auto &o : cb.tried)
        if (o.precision == baseline.budget.precision && o.fps == cb.fps)
          textureBytes = o.bytes, textureError = o.maxErrorMm;
      // One pose decoded, every joint's matrix, at 200 times over the clip: from the tracks
      // (the palette pass's CPU mirror) and from the texture (the vertex shader's).
      const auto &packClip = baseline.pack.clips[k];
      const float duration = cc.clip.duration();
      t0 = Clock::now();
      float sink = 0;
      for (int i = 0; i < 200; ++i) {
        const float t = duration * float(i) / 199.0f;
        sink += crowd::runtime::skinningPalette(
            rig.skeleton, crowd::runtime::decodeLocalPose(rig.skeleton, cc.clip, t),
            baseline.pack.skeleton.inverseBind)[0][3][0];
      }
      const double tracksPoseUs = secondsSince(t0) / 200 * 1e6;
      t0 = Clock::now();
      for (int i = 0; i < 200; ++i) {
        const auto at = crowd::runtime::clipTimeAt(packClip, duration * float(i) / 199.0f);
        sink += crowd::runtime::sampleJoints(baseline.pack.animation, packClip, at.frame,
                                             at.alpha)[0][0]
                    .w;
      }
      const double texturePoseUs = secondsSince(t0) / 200 * 1e6;
      if (sink == 12345.678f)
        std::printf(" ");
      const std::string clipName = clip.name.empty() ? "clip" + std::to_string(k) : clip.name;
      auto a = acl.find(model + "/" + clipName);
      if (a == acl.end())
        a = acl.find(model + "/clip" + std::to_string(k));
      const long aclB = a == acl.end() ? 0 : a->second.bytes;
      const double aclMs = a == acl.end() ? 0 : a->second.ms;
      modelTracks += long(f.bytes);
      modelAcl += aclB;
      modelAclMs += aclMs;
      totalTracks += long(f.bytes);
      totalTexture += long(textureBytes);
      if (aclB) {
        totalAcl += aclB;
        tracksWithAcl += long(f.bytes);
        textureWithAcl += long(textureBytes);
      }
      std::printf(
          "%-28s %-14s %5u %5u %9llu %8.3f %9llu %8.3f %8s %6s %6.3f %7.1f %7.1f%s\n",
          model.substr(0, 28).c_str(), clipName.substr(0, 14).c_str(), f.keys, f.samples,
          (unsigned long long)f.bytes, f.maxAnyTimeMm(), (unsigned long long)textureBytes,
          textureError, aclB ? std::to_string(aclB).c_str() : "-",
          aclB ? (std::ostringstream() << double(f.bytes) / double(aclB)).str().substr(0, 5).c_str()
               : "-",
          textureBytes ? double(f.bytes) / double(textureBytes) : 0.0, tracksPoseUs, texturePoseUs,
          f.met ? "" : "  MISSES the budget");
      csv << model << ',' << clipName << ',' << c.jointCount() << ',' << f.keys << ',' << f.samples
          << ',' << f.defaultTracks << ',' << f.constantTracks << ',' << f.animatedTracks << ','
          << f.meanBits << ',' << f.bytes << ',' << f.maxAnyTimeMm() << ',' << f.maxAtSamplesMm
          << ',' << f.maxAtMidsMm << ',' << f.maxAtRandomMm << ',' << trackTime << ','
          << tracksPoseUs << ',' << textureBytes << ',' << textureError << ','
          << textureTime / double(c.clips.size()) << ',' << texturePoseUs << ',' << aclB << ','
          << aclMs << '\n';
    }
    std::printf("%-28s skeleton %llu bytes (shared by its clips), texture bake %.2f s\n", "",
                (unsigned long long)crowd::pack::skeletonBytes(rig.skeleton), textureTime);
    if (modelAcl > 0)
      std::printf("%-28s against ACL: clips %ld bytes vs %ld (%.3fx); tracks compressed in "
                  "%.1f ms vs %.1f ms (%.0fx); the default bake %.2f s (%.0fx)\n",
                  "", modelTracks, modelAcl, double(modelTracks) / double(modelAcl),
                  modelTracksSeconds * 1e3, modelAclMs,
                  modelTracksSeconds * 1e3 / std::max(modelAclMs, 1e-3), defaultTime,
                  defaultTime * 1e3 / std::max(modelAclMs, 1e-3));
  }
  std::printf("\nclips ACL measured: tracks %ld bytes, ACL %ld (%.3fx), texture %ld (%.1fx ACL)\n",
              tracksWithAcl, totalAcl, totalAcl ? double(tracksWithAcl) / double(totalAcl) : 0.0,
              textureWithAcl, totalAcl ? double(textureWithAcl) / double(totalAcl) : 0.0);
  std::printf("every clip: tracks %ld bytes, texture %ld (%.3fx); bake time tracks %.2f s, "
              "texture %.2f s (%.2fx)\n",
              totalTracks, totalTexture,
              totalTexture ? double(totalTracks) / double(totalTexture) : 0.0, tracksSeconds,
              textureSeconds, textureSeconds > 0 ? tracksSeconds / textureSeconds : 0.0);
  if (!csvPath.empty())
    std::ofstream(csvPath) << csv.str();
  return 0;
}
