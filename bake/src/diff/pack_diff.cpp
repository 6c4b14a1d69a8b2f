#include "crowd/bake/pack_diff.h"
#include "crowd/formats/registry.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <optional>

#include <glm/glm.hpp>

#include "crowd/bake/anim_bake.h"
#include "crowd/formats/chunks.h"
#include "crowd/formats/cloth.h"
#include "crowd/formats/error.h"
#include "crowd/formats/impostor.h"
#include "crowd/formats/terrain.h"
#include "crowd/runtime/pack_joints.h"

namespace crowd {

namespace {

using Pair = DiffTolerances::Pair;
using nlohmann::ordered_json;

// The tolerance pairs by their JSON names: the one list tolerancesFromJson and tolerancesJson read.
std::vector<std::pair<const char *, Pair DiffTolerances::*>> tolerancePairs() {
  return {{"animation_mm", &DiffTolerances::animationMm},
          {"weight", &DiffTolerances::weight},
          {"position_mm", &DiffTolerances::positionMm},
          {"normal_deg", &DiffTolerances::normalDeg},
          {"uv", &DiffTolerances::uv},
          {"lod_error", &DiffTolerances::lodError},
          {"cloth_mm", &DiffTolerances::clothMm},
          {"texel", &DiffTolerances::texel},
          {"texel_relative", &DiffTolerances::texelRelative},
          {"texel_percent", &DiffTolerances::texelPercent}};
}

DiffVerdict grade(double value, Pair p) {
  return value <= p.warn   ? DiffVerdict::Pass
         : value <= p.fail ? DiffVerdict::Warn
                           : DiffVerdict::Fail;
}

std::string format(const char *fmt, double v) {
  char b[64];
  std::snprintf(b, sizeof b, fmt, v);
  return b;
}

// A chunk of one pack, keyed by what it holds (type, and for impostors and loops, their pair).
struct Keyed {
  std::string key;
  const pack::ChunkEntry *entry;
  std::span<const uint8_t> payload;
};

std::vector<Keyed> keyedChunks(const pack::Reader &r) {
  std::vector<Keyed> out;
  for (const auto &c : r.chunks()) {
    std::string key = pack::fourccName(c.type);
    const std::string ctx = r.name() + ": chunk " + key;
    if (c.type == pack::kImpostor) {
      const auto m = pack::decodeImpostor(r.payload(c), c.version, ctx);
      key += " " + m.clip + "/" + (m.outfit.empty() ? "body" : m.outfit);
    } else if (c.type == pack::kCloth) {
      const auto l = pack::decodeClothLoop(r.payload(c), ctx);
      key += " " + l.outfit + "/" + l.garment + "/" + l.clip;
    }
    out.push_back({key, &c, r.payload(c)});
  }
  return out;
}

// The chunks both packs hold, decoded on demand.
struct Side {
  const pack::Reader &reader;
  std::map<std::string, Keyed> chunks;
  std::span<const uint8_t> payload(const std::string &key) const { return chunks.at(key).payload; }
  std::string context(const std::string &key) const { return reader.name() + ": chunk " + key; }
  bool has(const std::string &key) const { return chunks.count(key) > 0; }
};

bool samePayload(const Side &a, const Side &b, const std::string &key) {
  const auto x = a.payload(key), y = b.payload(key);
  return x.size() == y.size() && std::equal(x.begin(), x.end(), y.begin());
}

// Model units to mm, the mesh's bind pose 1.8 m tall (its diagonal where it is flat).
double millimetresPerUnit(const pack::Mesh &m) {
  glm::dvec3 lo(INFINITY), hi(-INFINITY);
  for (size_t v = 0; v < m.vertexCount(); ++v) {
    const glm::dvec3 p(m.positions[v * 3], m.positions[v * 3 + 1], m.positions[v * 3 + 2]);
    lo = glm::min(lo, p), hi = glm::max(hi, p);
  }
  const glm::dvec3 extent = hi - lo;
  const double diagonal = glm::length(extent);
  const double height = extent.y >= 0.1 * diagonal ? extent.y : diagonal;
  return height > 0 ? kReferenceHeightMm / height : 0;
}

// The animation group of one pack, read as the player reads it (its chunks checked against each
// other: joint ids, frame ranges, vertex counts).
struct Animated : pack::AnimationPack {
  explicit Animated(const Side &s) : pack::AnimationPack(pack::loadAnimationPack(s.reader)) {}
  // Vertex v at `seconds` into clip c, as the player draws it; the joints are sampled once per
  // time (the last time asked is kept).
  glm::vec3 at(const pack::Clip &c, float seconds, uint32_t v) {
    const runtime::ClipTime t = runtime::clipTimeAt(c, seconds);
    if (sampledClip_ != &c || sampledFrame_ != t.frame || sampledAlpha_ != t.alpha) {
      joints_ = runtime::sampleJoints(*this, size_t(&c - clips.data()), t.frame, t.alpha);
      sampledClip_ = &c, sampledFrame_ = t.frame, sampledAlpha_ = t.alpha;
    }
    runtime::SkinnedVertex bind{
        {mesh.positions[v * 3], mesh.positions[v * 3 + 1], mesh.positions[v * 3 + 2]},
        glm::vec3(0.0f)};
    if (morphs)
      bind = runtime::morphVertex(*morphs, t, v, bind);
    return runtime::skinVertex(joints_, skin, v, bind.position);
  }

private:
  std::vector<runtime::JointRows> joints_;
  const pack::Clip *sampledClip_ = nullptr;
  uint32_t sampledFrame_ = 0;
  float sampledAlpha_ = -1;
};

// Frame and mid-frame times of a clip, seconds into it.
void addTimes(const pack::Clip &c, std::vector<float> &times) {
  for (uint32_t k = 0; k < c.frameCount; ++k) {
    times.push_back(float(k) / c.fps);
    if (k + 1 < c.frameCount)
      times.push_back((float(k) + 0.5f) / c.fps);
  }
}

class Differ {
public:
  Differ(const pack::Reader &g, const pack::Reader &n, const DiffTolerances &t)
      : golden_{g, {}}, fresh_{n, {}}, tol_(t) {
    for (auto &k : keyedChunks(g))
      golden_.chunks.emplace(k.key, k);
    for (auto &k : keyedChunks(n))
      fresh_.chunks.emplace(k.key, k);
  }

  PackDiff run() {
    if (golden_.has("MESH"))
      out_.mmPerUnit =
          millimetresPerUnit(pack::decodeMesh(golden_.payload("MESH"), golden_.context("MESH")));
    // The animation stored as a texture on one side and as joint tracks on the other (or
    // both): compared where the player puts each vertex, as for any other change.
    const bool animations = stored(golden_) && stored(fresh_);
    for (const auto &[key, c] : golden_.chunks)
      if (!fresh_.has(key))
        onlyIn(key, "golden", animations);
    for (const auto &[key, c] : fresh_.chunks)
      if (!golden_.has(key))
        onlyIn(key, "new", animations);
    if (animations &&
        (golden_.has("ANIM") != fresh_.has("ANIM") || golden_.has("TRAK") != fresh_.has("TRAK")))
      animationGroup("ANIM");
    for (const auto &[key, c] : golden_.chunks) {
      if (!fresh_.has(key))
        continue;
      if (samePayload(golden_, fresh_, key)) {
        DiffItem same{key, "bytes", 0, "", "", DiffVerdict::Pass};
        same.identical = true;
        add(same);
        continue;
      }
      compare(key);
    }
    return out_;
  }

private:
  void add(DiffItem item) {
    out_.verdict = std::max(out_.verdict, item.informational ? DiffVerdict::Pass : item.verdict);
    out_.items.push_back(std::move(item));
  }
  static bool stored(const Side &s) { return s.has("ANIM") || s.has("TRAK"); }
  void onlyIn(const std::string &key, const char *side, bool animations) {
    const std::string text = std::string("only in the ") + side + " pack";
    if (animations && (key == "ANIM" || key == "TRAK"))
      informational(key, "chunk", text + ": compared through the animation displacement");
    else
      add({key, "chunk", 0, "", text, DiffVerdict::Incomparable});
  }
  void incomparable(const std::string &key, const std::string &why) {
    add({key, "structure", 0, "", why, DiffVerdict::Incomparable});
  }
  void informational(const std::string &key, const std::string &what, const std::string &text) {
    DiffItem i{key, what, 0, "", text, DiffVerdict::Pass};
    i.informational = true;
    add(i);
  }

  // The comparison of each chunk type that has one of its own, by tolerance where the player
  // shows the difference (a new type adds its line here); any other type (outfits, vertex
  // sources, a registered type) is compared by its codec's description, exactly.
  using Comparison = void (Differ::*)(const std::string &);
  static const std::map<std::string, Comparison> &comparisons() {
    static const std::map<std::string, Comparison> table = {
        {"PROV", &Differ::provenance},     {"SKEL", &Differ::animationGroup},
        {"CLIP", &Differ::animationGroup}, {"ANIM", &Differ::animationGroup},
        {"TRAK", &Differ::animationGroup}, {"MRPH", &Differ::animationGroup},
        {"SKIN", &Differ::skin},           {"MESH", &Differ::mesh},
        {"TEXR", &Differ::diffuse},        {"LODS", &Differ::lod},
        {"IMPO", &Differ::impostor},       {"CLTH", &Differ::cloth},
        {"TERR", &Differ::terrain}};
    return table;
  }
  void compare(const std::string &key) {
    const auto it = comparisons().find(key.substr(0, 4));
    if (it != comparisons().end())
      (this->*it->second)(key);
    else
      byDescription(key);
  }

  // A chunk type without a comparison of its own: the two chunks as their codec describes them
  // (what inspect prints), the first field or table cell that differs named; any difference
  // fails.
  void byDescription(const std::string &key) {
    const pack::ChunkEntry &ea = *golden_.chunks.at(key).entry, &eb = *fresh_.chunks.at(key).entry;
    std::string where;
    if (ea.version != eb.version)
      where = "chunk version " + std::to_string(ea.version) + " -> " + std::to_string(eb.version);
    else if (const pack::ChunkCodec *codec = pack::findCodec(ea.type))
      where =
          firstDifference(codec->describe(golden_.payload(key), ea.version, golden_.context(key)),
                          codec->describe(fresh_.payload(key), eb.version, fresh_.context(key)));
    if (where.empty())
      where = "differs in bytes, not in what its codec describes";
    add({key, "content", 1, "", where + " (compared exactly)", DiffVerdict::Fail});
  }

  static std::string firstDifference(const pack::Description &a, const pack::Description &b) {
    for (size_t f = 0; f < std::max(a.fields.size(), b.fields.size()); ++f) {
      const bool inA = f < a.fields.size(), inB = f < b.fields.size();
      if (inA && inB && a.fields[f].key == b.fields[f].key &&
          a.fields[f].value.text == b.fields[f].value.text)
        continue;
      return "field '" + (inA ? a.fields[f].key : b.fields[f].key) +
             "': " + (inA ? a.fields[f].value.text : "-") + " -> " +
             (inB ? b.fields[f].value.text : "-");
    }
    for (size_t t = 0; t < std::min(a.tables.size(), b.tables.size()); ++t) {
      const auto &ta = a.tables[t], &tb = b.tables[t];
      if (ta.rows.size() != tb.rows.size())
        return "table '" + ta.name + "': " + std::to_string(ta.rows.size()) + " -> " +
               std::to_string(tb.rows.size()) + " rows";
      for (size_t r = 0; r < ta.rows.size(); ++r)
        for (size_t c = 0; c < std::min(ta.rows[r].size(), tb.rows[r].size()); ++c)
          if (ta.rows[r][c].text != tb.rows[r][c].text)
            return "table '" + ta.name + "', row " + std::to_string(r) + ", " +
                   (c < ta.columns.size() ? ta.columns[c] : "column " + std::to_string(c)) + ": " +
                   ta.rows[r][c].text + " -> " + tb.rows[r][c].text;
    }
    return "";
  }

  void provenance(const std::string &key) {
    const auto a = pack::decodeProvenance(golden_.payload(key), golden_.context(key));
    const auto b = pack::decodeProvenance(fresh_.payload(key), fresh_.context(key));
    std::string text;
    auto note = [&](const std::string &s) { text += (text.empty() ? "" : "; ") + s; };
    if (a.bakerVersion != b.bakerVersion)
      note("baker " + a.bakerVersion + " -> " + b.bakerVersion);
    std::map<std::string, std::string> sa(a.settings.begin(), a.settings.end()),
        sb(b.settings.begin(), b.settings.end());
    for (const auto &[k, v] : sa)
      if (!sb.count(k) || sb[k] != v)
        note("setting " + k);
    for (const auto &[k, v] : sb)
      if (!sa.count(k))
        note("setting " + k);
    const size_t inputs = std::max(a.inputs.size(), b.inputs.size());
    for (size_t i = 0; i < inputs; ++i)
      if (i >= a.inputs.size() || i >= b.inputs.size() || a.inputs[i].hash != b.inputs[i].hash ||
          a.inputs[i].path != b.inputs[i].path)
        note("input " + (i < b.inputs.size() ? b.inputs[i].path : a.inputs[i].path));
    informational(key, "provenance", text.empty() ? "differs" : text);
  }

  // Skeleton, clips, animation (texture or joint tracks) and morphs together: where the player
  // puts each vertex.
  void animationGroup(const std::string &key) {
    if (animationDone_)
      return informational(key, "animation", "compared through the animation displacement");
    animationDone_ = true;
    for (const char *k : {"SKEL", "CLIP", "SKIN", "MESH"})
      if (!golden_.has(k) || !fresh_.has(k))
        return incomparable(key, std::string("no ") + k + " chunk to skin with");
    if (!stored(golden_) || !stored(fresh_))
      return incomparable(key, "no ANIM or TRAK chunk to skin with");
    Animated a(golden_), b(fresh_);
    if (a.skeleton.names != b.skeleton.names || a.skeleton.parents != b.skeleton.parents)
      return incomparable("SKEL", "the joints differ (names or parents)");
    if (a.mesh.vertexCount() != b.mesh.vertexCount())
      return incomparable("MESH", std::to_string(a.mesh.vertexCount()) + " vertices against " +
                                      std::to_string(b.mesh.vertexCount()));
    std::vector<std::string> na, nb;
    for (const auto &c : a.clips)
      na.push_back(c.name);
    for (const auto &c : b.clips)
      nb.push_back(c.name);
    if (na != nb)
      return incomparable("CLIP", "the clips differ (names or order)");
    DiffItem worst{"ANIM", "animation displacement", 0, "mm", "", DiffVerdict::Pass};
    for (size_t ci = 0; ci < a.clips.size(); ++ci) {
      std::vector<float> times;
      addTimes(a.clips[ci], times);
      addTimes(b.clips[ci], times);
      for (float t : times)
        for (uint32_t v = 0; v < a.mesh.vertexCount(); ++v) {
          const double mm =
              glm::length(a.at(a.clips[ci], t, v) - b.at(b.clips[ci], t, v)) * out_.mmPerUnit;
          if (mm > worst.value) {
            worst.value = mm;
            worst.worst = "clip '" + a.clips[ci].name + "', t " + format("%.4f", t) +
                          " s, vertex " + std::to_string(v) + " (joint '" +
                          a.skeleton.names.at(heaviestJoint(a.skin, v)) + "')";
          }
        }
    }
    worst.verdict = grade(worst.value, tol_.animationMm);
    add(worst);
  }

  static uint32_t heaviestJoint(const pack::SkinTexture &s, uint32_t v) {
    const float *w = &s.texels[size_t(v) * 8 + 4];
    return uint32_t(s.texels[size_t(v) * 8 + size_t(std::max_element(w, w + 4) - w)]);
  }

  void skin(const std::string &key) {
    const auto a = pack::decodeSkinTexture(golden_.payload(key), golden_.context(key));
    const auto b = pack::decodeSkinTexture(fresh_.payload(key), fresh_.context(key));
    if (a.vertexCount != b.vertexCount)
      return incomparable(key, "vertex counts differ");
    DiffItem item{key, "skin weights", 0, "", "", DiffVerdict::Pass};
    for (uint32_t v = 0; v < a.vertexCount; ++v) {
      std::map<int, float> wa, wb; // joint -> weight, the influences with weight
      for (int k = 0; k < 4; ++k) {
        if (a.texels[size_t(v) * 8 + 4 + size_t(k)] > 0)
          wa[int(a.texels[size_t(v) * 8 + size_t(k)])] += a.texels[size_t(v) * 8 + 4 + size_t(k)];
        if (b.texels[size_t(v) * 8 + 4 + size_t(k)] > 0)
          wb[int(b.texels[size_t(v) * 8 + size_t(k)])] += b.texels[size_t(v) * 8 + 4 + size_t(k)];
      }
      bool same = wa.size() == wb.size();
      for (const auto &[j, w] : wa) {
        same = same && wb.count(j);
        if (same && std::abs(w - wb[j]) > item.value) {
          item.value = std::abs(w - wb[j]);
          item.worst = "vertex " + std::to_string(v) + ", joint " + std::to_string(j);
        }
      }
      if (!same) {
        item.value = 1;
        item.worst = "vertex " + std::to_string(v) + ": other joints influence it";
        item.verdict = DiffVerdict::Fail;
        return add(item);
      }
    }
    item.verdict = grade(item.value, tol_.weight);
    add(item);
  }

  void mesh(const std::string &key) {
    const auto a = pack::decodeMesh(golden_.payload(key), golden_.context(key));
    const auto b = pack::decodeMesh(fresh_.payload(key), fresh_.context(key));
    if (a.vertexCount() != b.vertexCount() || a.uvs.size() != b.uvs.size())
      return incomparable(key, "vertex counts or UV sets differ");
    if (a.indices != b.indices) {
      // A triangle that starts at another corner is the same triangle, wound the same way, as
      // meshopt's index codec (gltfpack -c) may write it: drawn alike, so counted, not failed.
      const auto sameTriangle = [&](size_t t) {
        for (size_t r = 0; r < 3; ++r)
          if (a.indices[t] == b.indices[t + r] && a.indices[t + 1] == b.indices[t + (r + 1) % 3] &&
              a.indices[t + 2] == b.indices[t + (r + 2) % 3])
            return true;
        return false;
      };
      size_t k = 0, turned = 0;
      for (; k < a.indices.size() && a.indices.size() == b.indices.size(); k += 3) {
        if (!sameTriangle(k))
          break;
        turned += a.indices[k] != b.indices[k];
      }
      if (k < a.indices.size() || a.indices.size() != b.indices.size())
        return add({key, "triangles", 1, "", "they differ from triangle " + std::to_string(k / 3),
                    DiffVerdict::Fail});
      add({key, "triangles starting at another corner", double(turned), "",
           "the same triangles, the same winding", DiffVerdict::Pass});
    }
    DiffItem pos{key, "bind-pose positions", 0, "mm", "", DiffVerdict::Pass};
    DiffItem nrm{key, "bind-pose normals", 0, "deg", "", DiffVerdict::Pass};
    DiffItem uv{key, "texture coordinates", 0, "", "", DiffVerdict::Pass};
    for (size_t v = 0; v < a.vertexCount(); ++v) {
      const glm::vec3 pa(a.positions[v * 3], a.positions[v * 3 + 1], a.positions[v * 3 + 2]);
      const glm::vec3 pb(b.positions[v * 3], b.positions[v * 3 + 1], b.positions[v * 3 + 2]);
      const glm::vec3 na(a.normals[v * 3], a.normals[v * 3 + 1], a.normals[v * 3 + 2]);
      const glm::vec3 nb(b.normals[v * 3], b.normals[v * 3 + 1], b.normals[v * 3 + 2]);
      const std::string where = "vertex " + std::to_string(v);
      worse(pos, glm::length(pa - pb) * out_.mmPerUnit, where);
      // atan2 of |cross| and dot: exact near 0 degrees, where acos of a float dot is not.
      const glm::dvec3 da(na), db(nb);
      worse(nrm, glm::degrees(std::atan2(glm::length(glm::cross(da, db)), glm::dot(da, db))),
            where);
      if (!a.uvs.empty())
        worse(uv,
              std::max(std::abs(a.uvs[v * 2] - b.uvs[v * 2]),
                       std::abs(a.uvs[v * 2 + 1] - b.uvs[v * 2 + 1])),
              where);
    }
    pos.verdict = grade(pos.value, tol_.positionMm);
    nrm.verdict = grade(nrm.value, tol_.normalDeg);
    uv.verdict = grade(uv.value, tol_.uv);
    add(pos), add(nrm), add(uv);
  }

  static void worse(DiffItem &item, double value, const std::string &where) {
    if (value > item.value)
      item.value = value, item.worst = where;
  }

  // Texels in 0..1 per channel, idiff-style: a channel counts as changed past a tolerance when
  // its absolute change exceeds `texel` and its change relative to the mean of the two values
  // exceeds `texel_relative`; the item is the largest change that counts for warn and the
  // percent of texels past the fail tolerances. `exact` channels (region ids) must not change.
  void texels(const std::string &key, const std::string &what, size_t count, int channels,
              const std::function<double(int which, size_t texel, int channel)> &value,
              const std::vector<int> &exact = {}) {
    DiffItem item{key, what, 0, "", "", DiffVerdict::Pass};
    size_t over = 0, exactOff = 0;
    for (size_t t = 0; t < count; ++t) {
      double most = 0;
      bool failing = false;
      for (int c = 0; c < channels; ++c) {
        const double a = value(0, t, c), b = value(1, t, c), d = std::abs(a - b);
        if (std::find(exact.begin(), exact.end(), c) != exact.end()) {
          if (d != 0 && exactOff++ == 0)
            item.worst = "texel " + std::to_string(t) + ": region id changed";
          continue;
        }
        const double mean = 0.5 * (std::abs(a) + std::abs(b));
        const double relative = mean > 0 ? d / mean : 0;
        if (relative > tol_.texelRelative.warn)
          most = std::max(most, d);
        failing |= d > tol_.texel.fail && relative > tol_.texelRelative.fail;
      }
      over += failing;
      if (most > item.value) {
        item.value = most;
        if (!exactOff)
          item.worst = "texel " + std::to_string(t);
      }
    }
    const double percent = count ? 100.0 * double(over) / double(count) : 0;
    item.verdict =
        std::max(grade(item.value, {tol_.texel.warn, INFINITY}), grade(percent, tol_.texelPercent));
    if (exactOff) {
      item.verdict = DiffVerdict::Fail;
      item.worst += " (" + std::to_string(exactOff) + " texels' region ids changed)";
    } else if (over) {
      item.worst += " (" + format("%.4g", percent) + "% of texels over the fail tolerance)";
    }
    add(item);
  }

  void diffuse(const std::string &key) {
    const auto a = pack::decodeTexture(golden_.payload(key), golden_.context(key));
    const auto b = pack::decodeTexture(fresh_.payload(key), fresh_.context(key));
    if (a.width != b.width || a.height != b.height)
      return incomparable(key, "texture sizes differ");
    const pack::Texture *t[2] = {&a, &b};
    texels(key, "diffuse texels", size_t(a.width) * a.height, 4,
           [&](int w, size_t i, int c) { return t[w]->rgba[i * 4 + size_t(c)] / 255.0; });
  }

  void lod(const std::string &key) {
    const auto a = pack::decodeLod(golden_.payload(key), golden_.context(key));
    const auto b = pack::decodeLod(fresh_.payload(key), fresh_.context(key));
    if (a.collapse.size() != b.collapse.size())
      return incomparable(key, "vertex counts differ");
    size_t first = 0;
    while (first < a.collapse.size() && a.collapse[first] == b.collapse[first])
      ++first;
    double largest = 0;
    for (float e : a.error)
      largest = std::max(largest, double(e));
    DiffItem item{key, "collapse error curve", 0, "of its largest", "", DiffVerdict::Pass};
    for (size_t k = 0; k < a.error.size(); ++k)
      worse(item, largest > 0 ? std::abs(double(a.error[k]) - b.error[k]) / largest : 0,
            "at " + std::to_string(k) + " vertices");
    item.worst += first == a.collapse.size()
                      ? " (same collapse order)"
                      : " (collapse order differs from vertex " + std::to_string(first) + ")";
    item.verdict = grade(item.value, tol_.lodError);
    add(item);
  }

  void impostor(const std::string &key) {
    const auto &ga = golden_.chunks.at(key), &fa = fresh_.chunks.at(key);
    const auto a = pack::decodeImpostor(ga.payload, ga.entry->version, golden_.context(key));
    const auto b = pack::decodeImpostor(fa.payload, fa.entry->version, fresh_.context(key));
    if (a.frames != b.frames || a.atlasWidth != b.atlasWidth || a.atlasHeight != b.atlasHeight ||
        a.uvs.size() != b.uvs.size() || a.views.size() != b.views.size())
      return incomparable(key, "atlas or view layouts differ");
    // Compared as the GPU samples them: every frame's decoded texels, in a row.
    std::vector<pack::ImpostorTexels> frames[2];
    for (uint32_t f = 0; f < a.frames; ++f)
      frames[0].push_back(pack::decodeTexels(a, f)), frames[1].push_back(pack::decodeTexels(b, f));
    const size_t per = a.frameTexels();
    auto at = [&](int w, size_t i) -> const pack::ImpostorTexels & { return frames[w][i / per]; };
    // The normal's xyz as n * 0.5 + 0.5; the region id + 1 (exact).
    texels(key, "normal atlas", a.frames * per, 4,
           [&](int w, size_t i, int c) {
             const auto &t = at(w, i);
             return c == 3 ? double(t.regions[i % per]) : t.normal(i % per)[size_t(c)] * 0.5 + 0.5;
           },
           {3});
    if (!a.uvs.empty())
      texels(key, "UV atlas", a.frames * per, 2, [&](int w, size_t i, int c) {
        return double(at(w, i).uv[(i % per) * 2 + size_t(c)]);
      });
  }

  void cloth(const std::string &key) {
    const auto a = pack::decodeClothLoop(golden_.payload(key), golden_.context(key));
    const auto b = pack::decodeClothLoop(fresh_.payload(key), fresh_.context(key));
    if (a.cacheStart != b.cacheStart || a.cycles != b.cycles ||
        a.positions.size() != b.positions.size() || a.vertexCount() != b.vertexCount() ||
        a.blendFrames != b.blendFrames)
      return add({key, "loop", 1, "",
                  "start " + std::to_string(a.cacheStart) + " -> " + std::to_string(b.cacheStart) +
                      ", cycles " + std::to_string(a.cycles) + " -> " + std::to_string(b.cycles) +
                      ", blend " + std::to_string(a.blendFrames) + " -> " +
                      std::to_string(b.blendFrames),
                  DiffVerdict::Fail});
    DiffItem item{key, "loop positions", 0, "mm", "", DiffVerdict::Pass};
    double squares = 0;
    const size_t n = a.positions.size() / 3, vc = std::max<size_t>(a.vertexCount(), 1);
    for (size_t i = 0; i < n; ++i) {
      glm::dvec3 d;
      for (int c = 0; c < 3; ++c)
        d[c] = (a.origin[size_t(c)] + a.step[size_t(c)] * a.positions[i * 3 + size_t(c)]) -
               (b.origin[size_t(c)] + b.step[size_t(c)] * b.positions[i * 3 + size_t(c)]);
      const double mm = glm::length(d) * out_.mmPerUnit;
      squares += mm * mm;
      worse(item, mm,
            "frame " + std::to_string(i / vc) + ", loop vertex " + std::to_string(i % vc));
    }
    item.worst += " (RMS " + format("%.4g", n ? std::sqrt(squares / double(n)) : 0.0) + " mm)";
    item.verdict = grade(item.value, tol_.clothMm);
    add(item);
  }

  // A terrain: the same grid and walkable map exactly; heights, shadow heights and the
  // environment's mesh within the position tolerance (model units are metres: 1000 mm each).
  void terrain(const std::string &key) {
    const auto a = pack::decodeTerrain(golden_.payload(key), golden_.context(key));
    const auto b = pack::decodeTerrain(fresh_.payload(key), fresh_.context(key));
    if (a.width != b.width || a.depth != b.depth || a.cell != b.cell || a.originX != b.originX ||
        a.originZ != b.originZ || a.positions.size() != b.positions.size() ||
        a.indices != b.indices)
      return incomparable(key, "another grid (" + std::to_string(b.width) + "x" +
                                   std::to_string(b.depth) + " cells) or another mesh");
    size_t ground = 0, first = 0;
    for (size_t i = 0; i < a.cells(); ++i)
      if (a.ground[i] != b.ground[i] && !ground++)
        first = i;
    add({key, "walkable map", double(ground), "cells",
         ground ? "first at cell (" + std::to_string(first % a.width) + ", " +
                      std::to_string(first / a.width) + ")"
                : "",
         ground ? DiffVerdict::Fail : DiffVerdict::Pass});
    auto compare = [&](const char *what, const std::vector<float> &x, const std::vector<float> &y,
                       bool cells) {
      DiffItem item{key, what, 0, "mm", "", DiffVerdict::Pass};
      for (size_t i = 0; i < x.size(); ++i)
        worse(item, 1000.0 * std::abs(double(x[i]) - y[i]),
              cells ? "cell (" + std::to_string(i % a.width) + ", " + std::to_string(i / a.width) +
                          ")"
                    : "vertex " + std::to_string(i / 3));
      item.verdict = grade(item.value, tol_.positionMm);
      add(item);
    };
    compare("heights", a.heights, b.heights, true);
    compare("shadow heights", a.shadowHeights, b.shadowHeights, true);
    compare("environment positions", a.positions, b.positions, false);
  }

  Side golden_, fresh_;
  const DiffTolerances &tol_;
  PackDiff out_;
  bool animationDone_ = false;
};

} // namespace

DiffTolerances tolerancesFromJson(const nlohmann::json &j, const std::string &context) {
  DiffTolerances t;
  if (!j.is_object())
    throw Error(context + ": the tolerances are not a JSON object");
  const auto pairs = tolerancePairs();
  for (const auto &[key, value] : j.items()) {
    auto it =
        std::find_if(pairs.begin(), pairs.end(), [&](const auto &p) { return key == p.first; });
    if (it == pairs.end())
      throw Error(context + ": unknown tolerance '" + key + "'");
    Pair &p = t.*(it->second);
    if (!value.is_object())
      throw Error(context + ": '" + key + "' is not {\"warn\": W, \"fail\": F}");
    for (const auto &[k, v] : value.items()) {
      if ((k != "warn" && k != "fail") || !v.is_number() || !(v.get<double>() >= 0))
        throw Error(context + ": '" + key + "/" + k +
                    "' must be \"warn\" or \"fail\" with a number >= 0");
      (k == "warn" ? p.warn : p.fail) = v.get<double>();
    }
    if (p.warn > p.fail)
      throw Error(context + ": '" + key + "': warn " + std::to_string(p.warn) + " is over fail " +
                  std::to_string(p.fail));
  }
  return t;
}

ordered_json tolerancesJson(const DiffTolerances &t) {
  ordered_json j;
  for (const auto &[key, member] : tolerancePairs())
    j[key] = {{"warn", (t.*member).warn}, {"fail", (t.*member).fail}};
  return j;
}

PackDiff diffPacks(const pack::Reader &golden, const pack::Reader &fresh,
                   const DiffTolerances &tolerances) {
  return Differ(golden, fresh, tolerances).run();
}

const char *name(DiffVerdict v) {
  switch (v) {
  case DiffVerdict::Pass:
    return "pass";
  case DiffVerdict::Warn:
    return "warn";
  case DiffVerdict::Fail:
    return "fail";
  case DiffVerdict::Incomparable:
    return "incomparable";
  }
  return "?";
}

ordered_json diffJson(const PackDiff &d, const DiffTolerances &t) {
  ordered_json j;
  j["verdict"] = name(d.verdict);
  j["exit_code"] = int(d.verdict);
  j["mm_per_model_unit"] = d.mmPerUnit;
  j["tolerances"] = tolerancesJson(t);
  j["items"] = ordered_json::array();
  for (const auto &i : d.items)
    j["items"].push_back({{"chunk", i.chunk},
                          {"what", i.what},
                          {"verdict", i.informational ? "listed" : name(i.verdict)},
                          {"identical", i.identical},
                          {"value", i.value},
                          {"unit", i.unit},
                          {"worst", i.worst}});
  return j;
}

} // namespace crowd
