#include "crowd/bake/anim_bake.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "crowd/bake/evaluate.h"
#include "crowd/bake/parallel.h"
#include "crowd/formats/error.h"
#include "crowd/formats/limits.h"
#include "crowd/runtime/texture_skinning.h"

namespace crowd {

const std::vector<Precision> &precisions() {
  using E = pack::JointEncoding;
  using F = pack::TexelFormat;
  static const std::vector<Precision> all = {{"float", E::Matrix3x4, F::RGBA32F},
                                             {"half", E::Matrix3x4, F::RGBA16F},
                                             {"qts", E::QuatTransScale, F::RGBA32F},
                                             {"qts-half", E::QuatTransScale, F::RGBA16F}};
  return all;
}

const Precision &precisionByName(const std::string &name) {
  for (const auto &p : precisions())
    if (p.name == name)
      return p;
  throw Error("unknown precision '" + name + "' (float, half, qts, qts-half)");
}

namespace {

struct ClipFrames {
  const AnimationClip *clip; // null: rest pose
  std::string name;
  double start, step; // frame i sits at start + i * step
  uint32_t count;
  double fps;
};

// Texels of one joint: 3 matrix rows, or quaternion + (translation, uniform scale).
void encodeJoint(const glm::dmat4 &m, pack::JointEncoding enc, float *out) {
  if (enc == pack::JointEncoding::Matrix3x4) {
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c)
        out[r * 4 + c] = float(m[c][r]);
    return;
  }
  glm::dmat3 a(m);
  double s = std::cbrt(glm::determinant(a));
  if (s == 0)
    s = 1e-30;
  glm::dquat q = glm::normalize(glm::quat_cast(a / s));
  if (q.w < 0)
    q = -q; // canonical sign; the sampler picks the short arc between frames
  const double v[8] = {q.x, q.y, q.z, q.w, m[3][0], m[3][1], m[3][2], s};
  for (int k = 0; k < 8; ++k)
    out[k] = float(v[k]);
}

pack::AnimationTexture buildTexture(const std::vector<std::vector<glm::dmat4>> &frames,
                                    size_t jointCount, const Precision &p, uint32_t maxWidth) {
  pack::AnimationTexture t;
  t.encoding = p.encoding;
  t.format = p.format;
  t.jointCount = uint32_t(jointCount);
  t.frameCount = uint32_t(frames.size());
  uint64_t frameTexels = uint64_t(jointCount) * pack::texelsPerJoint(p.encoding);
  t.framesPerRow = uint32_t(maxWidth / frameTexels);
  if (t.framesPerRow == 0)
    throw Error("a frame of " + std::to_string(jointCount) + " joints needs " +
                std::to_string(frameTexels) + " texels, more than --max-width " +
                std::to_string(maxWidth));
  t.framesPerRow = std::min(t.framesPerRow, t.frameCount);
  t.width = uint32_t(t.framesPerRow * frameTexels);
  t.height = (t.frameCount + t.framesPerRow - 1) / t.framesPerRow;
  if (t.height > limits::kTextureSide)
    throw Error("animation texture would be taller than " + std::to_string(limits::kTextureSide) +
                " rows");
  size_t texelCount = size_t(t.width) * t.height;
  std::vector<float> values(texelCount * 4, 0.0f);
  for (uint32_t f = 0; f < t.frameCount; ++f)
    for (uint32_t j = 0; j < jointCount; ++j) {
      auto [x, y] = t.texelOf(f, j);
      encodeJoint(frames[f][j], p.encoding, &values[(size_t(y) * t.width + x) * 4]);
    }
  if (p.format == pack::TexelFormat::RGBA32F) {
    t.texels.resize(values.size() * 4);
    std::memcpy(t.texels.data(), values.data(), t.texels.size());
  } else {
    t.texels.resize(values.size() * 2);
    for (size_t i = 0; i < values.size(); ++i) {
      uint16_t h = pack::floatToHalf(values[i]);
      std::memcpy(&t.texels[i * 2], &h, 2);
    }
  }
  return t;
}

// Frames per second that put a frame on every key of the clip's densest channel (30 when the
// clip has one key), capped at 1000.
double sourceRate(const AnimationClip &clip) {
  double shortest = 0;
  for (const auto &ch : clip.channels)
    for (size_t k = 1; k < ch.times.size(); ++k) {
      double dt = ch.times[k] - ch.times[k - 1];
      if (dt > 1e-6 && (shortest == 0 || dt < shortest))
        shortest = dt;
    }
  return shortest > 0 ? std::min(1000.0, 1.0 / shortest) : 30.0;
}

pack::SkinTexture buildSkin(const SkinnedMesh &m, uint32_t maxWidth) {
  pack::SkinTexture s;
  s.vertexCount = uint32_t(m.vertexCount());
  uint64_t texels = uint64_t(s.vertexCount) * 2;
  s.width = uint32_t(std::min<uint64_t>(maxWidth & ~1u, texels));
  s.height = uint32_t((texels + s.width - 1) / s.width);
  if (s.height > limits::kTextureSide)
    throw Error("skin texture would be taller than " + std::to_string(limits::kTextureSide) +
                " rows");
  s.texels.assign(size_t(s.width) * s.height * 4, 0.0f);
  for (size_t v = 0; v < m.vertexCount(); ++v)
    for (int k = 0; k < 4; ++k) {
      s.texels[v * 8 + size_t(k)] = float(m.joints[v][size_t(k)]);
      s.texels[v * 8 + 4 + size_t(k)] = m.weights[v][k];
    }
  return s;
}

} // namespace

void AnimBakeOptions::validate() const {
  if (!(fps >= 0 && fps <= 1000))
    throw Error("fps: must be in (0, 1000], or source (0)");
  if (maxWidth < 2 || maxWidth > limits::kTextureSide)
    throw Error("max-width: must be in [2, " + std::to_string(limits::kTextureSide) + "]");
  if (threads < 0 || threads > 1024)
    throw Error("threads: must be in [0, 1024]");
  try {
    precisionByName(precision);
  } catch (const Error &e) {
    throw Error(std::string("precision: ") + e.what());
  }
}

AnimBakeResult bakeAnimation(const Character &c, const AnimBakeOptions &options,
                             Reporter &reporter) {
  options.validate();
  const Precision &chosen = precisionByName(options.precision);

  std::vector<ClipFrames> clips;
  for (const auto &clip : c.clips) {
    if (!options.clip.empty() && clip.name != options.clip)
      continue;
    double duration = clip.end - clip.start;
    double fps = options.fps > 0 ? options.fps : sourceRate(clip);
    double wanted = duration > 0 ? std::max(1.0, std::round(duration * fps)) : 0.0;
    if (wanted >= double(limits::kClipFrames)) // before the cast: an absurd duration overflows it
      throw Error("clip '" + clip.name + "': " + std::to_string(duration) + " s at " +
                  std::to_string(fps) + " fps needs more than " +
                  std::to_string(limits::kClipFrames) + " frames (use --fps or --clip)");
    auto intervals = uint32_t(wanted);
    ClipFrames cf{&clip,         clip.name,
                  clip.start,    intervals ? duration / intervals : 0.0,
                  intervals + 1, intervals ? intervals / duration : fps};
    clips.push_back(cf);
  }
  if (clips.empty()) {
    if (!options.clip.empty())
      throw unknownName("clip", options.clip, c.clipNames());
    reporter.warn("no_animation", "no animation: baked the rest pose as one-frame clip 'rest'");
    clips.push_back({nullptr, "rest", 0, 0, 1, options.fps > 0 ? options.fps : 30.0});
  }

  // Every frame's joint matrices and reference vertex positions, exact and in double.
  std::vector<std::pair<size_t, uint32_t>> frameList;
  for (size_t ci = 0; ci < clips.size(); ++ci)
    for (uint32_t i = 0; i < clips[ci].count; ++i)
      frameList.push_back({ci, i});
  size_t total = frameList.size();
  if (uint64_t(total) * c.mesh.vertexCount() > limits::kFrameVertices)
    throw Error(std::to_string(total) + " frames x " + std::to_string(c.mesh.vertexCount()) +
                " vertices is over the bake's limit of " + std::to_string(limits::kFrameVertices) +
                " (the accuracy check keeps every frame's positions): use --fps or --clip");
  std::vector<std::vector<glm::dmat4>> joints(total);
  std::vector<std::vector<glm::dvec3>> reference(total), midReference(total);
  parallelFor(total, options.threads, [&](size_t f) {
    const auto &cf = clips[frameList[f].first];
    uint32_t i = frameList[f].second;
    joints[f] = jointMatrices(c, cf.clip, cf.start + i * cf.step);
    reference[f] = skinPositions(c, joints[f]);
    if (i + 1 < cf.count)
      midReference[f] = skinPositions(c, jointMatrices(c, cf.clip, cf.start + (i + 0.5) * cf.step));
  });

  AnimBakeResult result;
  result.diagonal = restDiagonal(c);
  // A character's height is its extent along +y; a flat or lying asset (under a tenth of its
  // diagonal tall) is scaled by its diagonal instead.
  const double height = restExtent(c).y;
  result.heightIsDiagonal = !(height >= 0.1 * result.diagonal);
  result.mmPerUnit = kReferenceHeightMm / (result.heightIsDiagonal ? result.diagonal : height);
  auto &pk = result.pack;

  pk.skeleton.names.resize(c.jointCount());
  for (size_t j = 0; j < c.jointCount(); ++j) {
    pk.skeleton.names[j] = c.jointName(j);
    int parent = -1;
    for (int p = c.nodes[size_t(c.jointNodes[j])].parent; p >= 0 && parent < 0;
         p = c.nodes[size_t(p)].parent) {
      auto it = std::find(c.jointNodes.begin(), c.jointNodes.end(), p);
      if (it != c.jointNodes.end())
        parent = int(it - c.jointNodes.begin());
    }
    pk.skeleton.parents.push_back(parent);
    for (int k = 0; k < 16; ++k)
      pk.skeleton.inverseBind.push_back(float(c.inverseBind[j][k / 4][k % 4]));
  }

  uint32_t first = 0;
  for (const auto &cf : clips) {
    pack::Clip clip;
    clip.name = cf.name;
    clip.fps = float(cf.fps);
    clip.startTime = float(cf.start);
    clip.firstFrame = first;
    clip.frameCount = cf.count;
    double gap = 0;
    for (size_t v = 0; v < c.mesh.vertexCount(); ++v)
      gap = std::max(gap, glm::length(reference[first][v] - reference[first + cf.count - 1][v]));
    clip.loop = cf.count > 2 && gap <= 1e-4 * result.diagonal;
    pk.clips.push_back(clip);
    first += cf.count;
  }

  pk.skin = buildSkin(c.mesh, options.maxWidth); // the same for every precision
  // Accuracy of every precision, with the player's interpolation (runtime/texture_skinning),
  // at every frame time, every mid-frame time and kRandomTimesPerClip seeded random times.
  const auto &all = precisions();
  std::vector<pack::AnimationTexture> textures;
  for (const auto &p : all)
    textures.push_back(buildTexture(joints, c.jointCount(), p, options.maxWidth));
  const size_t np = all.size();
  const uint32_t vertexCount = uint32_t(c.mesh.vertexCount());
  // Error of every precision at (frame, alpha) of pack clip `ci` against `exact`: max[p], sum[p].
  auto measure = [&](size_t ci, uint32_t frame, float alpha, const std::vector<glm::dvec3> &exact,
                     double *max, double *sum) {
    for (size_t p = 0; p < np; ++p)
      for (uint32_t v = 0; v < vertexCount; ++v) {
        double e =
            glm::length(glm::dvec3(runtime::skinVertex(textures[p], pk.skin, pk.clips[ci], frame,
                                                       alpha, v, c.mesh.positions[v])) -
                        exact[v]);
        max[p] = std::max(max[p], e);
        sum[p] += e;
      }
  };
  std::vector<double> frameMax(total * np), frameSum(total * np), midMax(total * np),
      midSum(total * np);
  parallelFor(total, options.threads, [&](size_t f) {
    const size_t ci = frameList[f].first;
    const uint32_t i = frameList[f].second;
    measure(ci, i, 0.0f, reference[f], &frameMax[f * np], &frameSum[f * np]);
    if (!midReference[f].empty())
      measure(ci, i, 0.5f, midReference[f], &midMax[f * np], &midSum[f * np]);
  });
  // Random times: uniform over each clip's duration, from a fixed seed per clip.
  std::vector<std::pair<size_t, double>> randomTimes; // (clip, seconds into the clip)
  for (size_t ci = 0; ci < clips.size(); ++ci) {
    if (clips[ci].count < 2)
      continue;
    uint64_t state = 0x9e3779b97f4a7c15ull * (ci + 1);
    for (uint32_t k = 0; k < kRandomTimesPerClip; ++k) {
      state = state * 6364136223846793005ull + 1442695040888963407ull; // PCG's LCG step
      const double u = double(state >> 11) * 0x1.0p-53;
      randomTimes.push_back({ci, u * clips[ci].step * (clips[ci].count - 1)});
    }
  }
  std::vector<double> randomMax(randomTimes.size() * np), randomSum(randomTimes.size() * np);
  parallelFor(randomTimes.size(), options.threads, [&](size_t r) {
    const auto [ci, t] = randomTimes[r];
    const auto exact = skinPositions(c, jointMatrices(c, clips[ci].clip, clips[ci].start + t));
    uint32_t frame;
    float alpha;
    runtime::frameAt(pk.clips[ci], float(t), frame, alpha);
    measure(ci, frame, alpha, exact, &randomMax[r * np], &randomSum[r * np]);
  });

  for (size_t p = 0; p < np; ++p) {
    PrecisionAccuracy pa{all[p], textures[p].texels.size(), {}};
    size_t f = 0, r = 0;
    const double vc = double(vertexCount);
    for (size_t ci = 0; ci < pk.clips.size(); ++ci) {
      const pack::Clip &clip = pk.clips[ci];
      ClipAccuracy a{clip.name, clip.frameCount};
      for (uint32_t i = 0; i < clip.frameCount; ++i, ++f) {
        a.maxAtFrames = std::max(a.maxAtFrames, frameMax[f * np + p]);
        a.meanAtFrames += frameSum[f * np + p] / (vc * clip.frameCount);
        a.maxAtMidframes = std::max(a.maxAtMidframes, midMax[f * np + p]);
        if (clip.frameCount > 1)
          a.meanAtMidframes += midSum[f * np + p] / (vc * (clip.frameCount - 1));
      }
      for (; r < randomTimes.size() && randomTimes[r].first == ci; ++r) {
        a.maxAtRandom = std::max(a.maxAtRandom, randomMax[r * np + p]);
        a.meanAtRandom += randomSum[r * np + p] / (vc * kRandomTimesPerClip);
      }
      pa.clips.push_back(a);
    }
    if (all[p].name == chosen.name) {
      result.baked = result.accuracy.size();
      pk.animation = std::move(textures[p]);
    }
    result.accuracy.push_back(std::move(pa));
  }

  // Mesh, with a bounding sphere over every frame of every clip. Matrix blends keep mid-frame
  // positions inside the frames' hull; the baked precision's worst error is added on top.
  auto &mesh = pk.mesh;
  for (size_t v = 0; v < c.mesh.vertexCount(); ++v) {
    for (int k = 0; k < 3; ++k) {
      mesh.positions.push_back(c.mesh.positions[v][k]);
      mesh.normals.push_back(c.mesh.normals[v][k]);
    }
    if (!c.mesh.uvs.empty()) {
      mesh.uvs.push_back(c.mesh.uvs[v].x);
      mesh.uvs.push_back(c.mesh.uvs[v].y);
    }
  }
  mesh.indices = c.mesh.indices;
  if (c.mesh.sources.size() == c.mesh.vertexCount())
    pk.sources = pack::SourceMap::of(c.mesh.sources);
  if (c.diffuse && !c.mesh.uvs.empty())
    pk.diffuse =
        pack::Texture{uint32_t(c.diffuse->width), uint32_t(c.diffuse->height), c.diffuse->rgba};
  for (const auto &part : c.mesh.parts)
    mesh.subMeshes.push_back({part.name, part.firstIndex, part.indexCount});
  glm::dvec3 lo(INFINITY), hi(-INFINITY);
  for (const auto &frame : reference)
    for (const auto &q : frame) {
      lo = glm::min(lo, q);
      hi = glm::max(hi, q);
    }
  glm::dvec3 centre = (lo + hi) * 0.5;
  double radius = 0;
  for (const auto &frame : reference)
    for (const auto &q : frame)
      radius = std::max(radius, glm::length(q - centre));
  double slack = 0;
  for (const auto &a : result.accuracy[result.baked].clips)
    slack = std::max(slack, a.maxAnyTime());
  radius = (radius + slack) * (1 + 1e-6) + 1e-6 * result.diagonal;
  mesh.boundingSphere = {float(centre.x), float(centre.y), float(centre.z), float(radius)};
  return result;
}

} // namespace crowd
