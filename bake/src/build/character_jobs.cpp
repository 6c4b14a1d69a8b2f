// The jobs of a character build: mesh (outfits, LOD, animation), impostor per (clip, outfit),
// and the link that writes one character pack from their parts.
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <map>

#include "crowd/bake/anim_report.h"
#include "crowd/bake/bake_figures.h"
#include "crowd/bake/content_cache.h"
#include "crowd/bake/import.h"
#include "crowd/bake/job.h"
#include "crowd/bake/provenance.h"
#include "crowd/formats/character_pack.h"
#include "crowd/formats/error.h"

namespace crowd {

namespace {

using nlohmann::ordered_json;
using Clock = std::chrono::steady_clock;

double since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// A job's reporter: its warnings go to the part's figures, not stderr; its steps to the context.
Reporter jobReporter(const JobContext &context) {
  Reporter r;
  r.quiet = true;
  r.onStep = context.progress;
  return r;
}

ordered_json warnings(const Reporter &r) {
  ordered_json list = ordered_json::array();
  for (const auto &w : r.warnings())
    list.push_back({{"code", w.code}, {"message", w.message}, {"count", w.count}});
  return list;
}

// Keeps only the manifest's clips, in the manifest's order; an unknown name is an error that
// lists the file's clips.
void keepClips(Character &c, const std::vector<std::string> &names, const std::string &file) {
  if (names.empty())
    return;
  std::vector<AnimationClip> kept;
  for (const auto &name : names) {
    auto it = std::find_if(c.clips.begin(), c.clips.end(), [&](auto &k) { return k.name == name; });
    if (it == c.clips.end())
      throw Error(file + ": " + unknownName("clip", name, c.clipNames()).what());
    kept.push_back(*it);
  }
  c.clips = std::move(kept);
}

// A file of the manifest (its body or an outfit), read under the manifest's input policy.
Character importFile(const CharacterManifest &m, const std::string &file, Reporter &reporter,
                     const std::string &mesh = "") {
  ImportOptions io;
  io.input = m.input;
  io.mesh = mesh;
  return importGltf(file, io, reporter);
}

Character importBody(const CharacterManifest &m, Reporter &reporter) {
  Character body = importFile(m, m.body, reporter, m.mesh);
  keepClips(body, m.clips, m.body);
  return body;
}

std::string outfitFile(const CharacterManifest &m, const std::string &outfit) {
  for (const auto &[name, file] : m.outfits)
    if (name == outfit)
      return file;
  throw Error("character '" + m.name + "': no outfit named '" + outfit + "'");
}

void addChunks(Part &part, const std::vector<uint8_t> &packBytes, bool withProvenance) {
  pack::Reader r(packBytes, "part");
  for (const auto &c : r.chunks()) {
    if (c.type == pack::kProvenance && !withProvenance)
      continue;
    auto p = r.payload(c);
    part.chunks.push_back({c.type, c.version, {p.begin(), p.end()}});
  }
}

// Where an outfit impostor's region ids (body regions, then the outfit's garments) sit among
// the pack's sub-meshes: body regions keep their index; garment k is the k-th of the outfit's
// last `garments` sub-meshes (an outfit's own garments follow its copies).
std::vector<uint8_t> regionMap(const pack::Outfits &table, const std::string &outfit,
                               uint32_t bodyRegions, uint32_t garments, const std::string &ctx) {
  if (bodyRegions != table.bodySubMeshes)
    throw Error(ctx + ": " + std::to_string(bodyRegions) +
                " body regions, but the pack's body has " + std::to_string(table.bodySubMeshes) +
                " sub-meshes");
  auto it = std::find_if(table.outfits.begin(), table.outfits.end(),
                         [&](auto &o) { return o.name == outfit; });
  if (it == table.outfits.end() || it->subMeshes.size() < garments)
    throw Error(ctx + ": outfit '" + outfit + "' is not in the pack's outfit table");
  if (bodyRegions + garments > 255 || table.bodySubMeshes + table.colours.size() / 4 > 255)
    throw Error(ctx + ": more than 254 regions cannot be stored in an impostor");
  std::vector<uint8_t> map(256, 0); // by stored value (region + 1); 0 stays empty
  for (uint32_t r = 0; r < bodyRegions; ++r)
    map[r + 1] = uint8_t(r + 1);
  const size_t first = it->subMeshes.size() - garments;
  for (uint32_t g = 0; g < garments; ++g)
    map[bodyRegions + g + 1] = uint8_t(it->subMeshes[first + g] + 1);
  return map;
}

} // namespace

// Every cloth loop among `parts` (cloth jobs' parts), by the outfit it belongs to.
void addLoops(std::vector<OutfitInput> &outfits, const std::vector<const Part *> &parts) {
  for (const Part *part : parts)
    for (const auto &c : part->chunks) {
      if (c.type != pack::kCloth)
        continue;
      pack::ClothLoop loop = pack::decodeClothLoop(c.payload, "cloth part");
      for (auto &o : outfits)
        if (o.name == loop.outfit)
          o.loops.push_back(std::move(loop));
    }
}

Part meshJob(const Job &job, const std::vector<const Part *> &cloths, const JobContext &context) {
  const int threads = context.threads;
  const CharacterManifest &m = *job.character;
  const auto t0 = Clock::now();
  Reporter reporter = jobReporter(context);
  Character body = importBody(m, reporter);
  Part part;
  auto &f = part.figures;
  f["input_triangles"] = body.mesh.indices.size() / 3;
  f["joints"] = body.jointCount();
  f["import_s"] = since(t0);
  AnimBakeResult anim;
  if (m.outfits.empty()) {
    std::optional<pack::Lod> lod;
    if (m.lod) {
      const auto t1 = Clock::now();
      lod = applyLod(body, m.lodOptions, reporter);
      f["lod"] = lodFigures(*lod, f["input_triangles"]);
      f["lod"]["time_s"] = since(t1);
    }
    AnimBakeOptions ao = m.anim;
    ao.threads = threads;
    anim = bakeAnimation(body, ao, reporter);
    anim.pack.lod = std::move(lod);
  } else {
    std::vector<OutfitInput> outfits;
    for (const auto &[name, file] : m.outfits)
      outfits.push_back({name, importFile(m, file, reporter), {}});
    addLoops(outfits, cloths);
    OutfitOptions oo = m.outfitOptions;
    oo.anim = m.anim;
    oo.anim.threads = oo.visibility.threads = threads;
    if (m.lod)
      oo.lod = m.lodOptions;
    OutfitBakeResult r = bakeOutfits(body, outfits, oo, reporter);
    f.update(outfitFigures(r, oo));
    if (r.anim.pack.lod)
      f["lod"] = lodFigures(*r.anim.pack.lod, r.taggedFaces);
    anim = std::move(r.anim);
  }
  const auto &mesh = anim.pack.mesh;
  f["vertices"] = mesh.vertexCount();
  f["triangles"] = mesh.indices.size() / 3;
  f["sub_meshes"] = mesh.subMeshes.size();
  f.update(animFigures(anim));
  addChunks(part, pack::packBytes(anim.pack), false);
  f["time_s"] = since(t0);
  f["warnings"] = warnings(reporter);
  return part;
}

Part impostorJob(const Job &job, const std::vector<const Part *> &, const JobContext &context) {
  const int threads = context.threads;
  const CharacterManifest &m = *job.character;
  const auto t0 = Clock::now();
  Reporter reporter = jobReporter(context);
  Character c = importBody(m, reporter);
  uint32_t garments = 0;
  if (!job.outfit.empty()) {
    OutfitInput o{job.outfit, importFile(m, outfitFile(m, job.outfit), reporter), {}};
    garments = uint32_t(o.character.mesh.parts.size());
    c = dressCharacter(c, o, m.outfitOptions.regions, reporter);
  }
  ImpostorOptions opt = m.impostor;
  opt.clip = job.clip;
  opt.threads = threads;
  ImpostorBakeResult r = bakeImpostor(c, opt, reporter);
  r.impostor.outfit = job.outfit;
  Part part;
  part.chunks.push_back({pack::kImpostor, pack::kImpostorVersion, pack::encode(r.impostor)});
  auto &f = part.figures;
  f = impostorFigures(r, opt);
  f["outfit"] = job.outfit;
  f["body_regions"] = uint32_t(c.mesh.parts.size()) - garments;
  f["garment_regions"] = garments;
  if (opt.measure) {
    reporter.step("impostor accuracy: views against the mesh drawn");
    const auto t1 = Clock::now();
    f["accuracy"] = impostorAccuracyFigures(measureImpostor(c, r.impostor, threads));
    f["accuracy"]["time_s"] = since(t1);
  }
  f["time_s"] = since(t0);
  f["warnings"] = warnings(reporter);
  return part;
}

Part clothJob(const Job &job, const std::vector<const Part *> &, const JobContext &context) {
  const int threads = context.threads;
  const CharacterManifest &m = *job.character;
  const ClothEntry &e = m.cloth.at(job.cloth);
  const auto t0 = Clock::now();
  Reporter reporter = jobReporter(context);
  const Character body = importBody(m, reporter);
  const Character outfit = importFile(m, outfitFile(m, e.outfit), reporter);
  ClothBakeOptions opt = e.options;
  opt.loop.search.threads = opt.loop.edges.threads = threads;
  const ClothBakeResult r =
      bakeClothLoop(body, outfit, e.outfit, e.garment, e.clip, e.cache, m.input, opt, reporter);
  Part part;
  part.chunks.push_back({pack::kCloth, pack::kClothVersion, pack::encode(r.chunk)});
  part.figures = clothFigures(r);
  part.figures["time_s"] = since(t0);
  part.figures["warnings"] = warnings(reporter);
  return part;
}

Part terrainJob(const Job &job, const std::vector<const Part *> &, const JobContext &context) {
  const int threads = context.threads;
  const CharacterManifest &m = *job.character;
  const auto t0 = Clock::now();
  Reporter reporter = jobReporter(context);
  const Character environment = importFile(m, m.body, reporter, m.mesh);
  TerrainOptions options = m.terrain.value();
  options.threads = threads;
  const TerrainBakeResult r = bakeTerrain(environment, options, reporter);
  const pack::Terrain &t = r.terrain;
  Part part;
  part.chunks.push_back({pack::kTerrain, pack::kTerrainVersion, pack::encode(t)});
  part.figures["input_triangles"] = t.indices.size() / 3;
  part.figures["terrain"] = {{"cells", {t.width, t.depth}},
                             {"cell", t.cell},
                             {"walkable_cells", r.walkable},
                             {"blocked_cells", r.blocked},
                             {"unreachable_cells", r.unreachable},
                             {"empty_cells", r.empty},
                             {"walkable_cells_in_shadow", r.walkableInShadow},
                             {"max_shadow_depth", r.maxShadowDepth}};
  part.figures["time_s"] = since(t0);
  part.figures["warnings"] = warnings(reporter);
  return part;
}

Part linkJob(const Job &job, const std::vector<const Part *> &deps, const JobContext &) {
  const CharacterManifest &m = *job.character;
  const std::string ctx = "character '" + m.name + "'";
  Part part;
  part.chunks.push_back(provenanceChunk(job, "build"));
  const Part &mesh = *deps.at(0);
  part.chunks.insert(part.chunks.end(), mesh.chunks.begin(), mesh.chunks.end());
  std::optional<pack::Outfits> table;
  for (const auto &c : mesh.chunks)
    if (c.type == pack::kOutfits)
      table = pack::decodeOutfits(c.payload, ctx + ", OUTF");
  for (size_t d = 1; d < deps.size(); ++d) {
    const Part &imp = *deps[d];
    for (const auto &c : imp.chunks) {
      if (c.type == pack::kCloth) { // a cloth loop goes in as it is
        part.chunks.push_back(c);
        continue;
      }
      pack::Impostor m = pack::decodeImpostor(c.payload, c.version, ctx + ", IMPO");
      if (!m.outfit.empty()) { // re-number regions as the pack's sub-meshes
        if (!table)
          throw Error(ctx + ": an impostor of outfit '" + m.outfit + "' but no outfit table");
        auto map = regionMap(*table, m.outfit, imp.figures.at("body_regions").get<uint32_t>(),
                             imp.figures.at("garment_regions").get<uint32_t>(), ctx);
        for (uint8_t &region : m.regions)
          region = map[region];
      }
      part.chunks.push_back({pack::kImpostor, pack::kImpostorVersion, pack::encode(m)});
    }
  }
  const auto bytes = characterPackBytes(part);
  pack::loadCharacterPack(pack::Reader(bytes, m.name + ".crowdpack")); // cross-checks it all
  part.figures["pack_bytes"] = bytes.size();
  for (const auto &c : part.chunks)
    part.figures["chunk_bytes"].push_back(
        {{"type", pack::fourccName(c.type)}, {"bytes", c.payload.size()}});
  return part;
}

std::vector<Job> planCharacter(std::shared_ptr<const CharacterManifest> character, size_t base) {
  const CharacterManifest &m = *character;
  std::vector<Job> jobs;
  const ordered_json all = m.canonical();
  // A job hashes every file its imports read: a glTF's external buffers and images too.
  auto append = [&](std::vector<std::string> &to, const std::string &gltf) {
    for (auto &f : gltfFiles(gltf, m.input))
      to.push_back(std::move(f));
  };
  std::vector<std::string> bodyFiles, files;
  append(bodyFiles, m.body);
  files = bodyFiles;
  if (m.terrain) { // an environment: the terrain bake is its one job
    Job j;
    j.kind = "terrain";
    j.character = character;
    j.files = bodyFiles;
    j.settings = {{"mesh", m.mesh}, {"terrain", all["terrain"]}};
    return {j};
  }
  for (const auto &[name, file] : m.outfits)
    append(files, file);

  auto job = [&](const char *kind, std::vector<std::string> inputs, ordered_json settings) {
    Job j;
    j.kind = kind;
    j.character = character;
    j.files = std::move(inputs);
    j.settings = std::move(settings);
    return j;
  };
  // Cloth loops first: the mesh job's visibility tests their frames.
  std::vector<size_t> cloths;
  for (size_t i = 0; i < m.cloth.size(); ++i) {
    const ClothEntry &e = m.cloth[i];
    Job j =
        job("cloth", bodyFiles, {{"clips", m.clips}, {"mesh", m.mesh}, {"cloth", e.canonical()}});
    append(j.files, outfitFile(m, e.outfit));
    j.files.push_back(e.cache);
    j.clip = e.clip;
    j.outfit = e.outfit;
    j.cloth = i;
    cloths.push_back(base + jobs.size());
    jobs.push_back(j);
  }
  Job mesh = job("mesh", files, all);
  mesh.settings.erase("name"); // the same body and settings under another name share the part
  mesh.settings.erase("impostor");
  mesh.settings.erase("cloth"); // the loops reach it as parts: their keys are in its key
  mesh.deps = cloths;
  const size_t meshIndex = base + jobs.size();
  jobs.push_back(mesh);

  Job link = job("link", files, all);
  link.deps = {meshIndex};
  ordered_json impostorSettings = all.value("impostor", ordered_json::object());
  impostorSettings.erase("pairs"); // another pair list leaves this pair's part as it is
  for (const auto &[clip, outfit] : m.impostorPairs) {
    Job j = job("impostor", bodyFiles,
                {{"clips", m.clips},
                 {"mesh", m.mesh},
                 {"clip", clip},
                 {"outfit", outfit},
                 {"impostor", impostorSettings}});
    j.clip = clip;
    j.outfit = outfit;
    if (!outfit.empty()) {
      append(j.files, outfitFile(m, outfit));
      j.settings["regions"] = m.outfitOptions.regions;
    }
    link.deps.push_back(base + jobs.size());
    jobs.push_back(j);
  }
  link.deps.insert(link.deps.end(), cloths.begin(), cloths.end());
  jobs.push_back(link);
  return jobs;
}

} // namespace crowd
