// A character's mesh job (outfits, LOD, animation), its link job (one character pack from the
// parts of all its jobs), and planCharacter, which lists them all; the impostor, cloth and
// terrain jobs live in their bakes' folders.
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <map>

#include "crowd/bake/anim_report.h"
#include "crowd/bake/bake_figures.h"
#include "crowd/bake/content_cache.h"
#include "crowd/bake/import.h"
#include "crowd/bake/job.h"
#include "crowd/bake/job_inputs.h"
#include "crowd/bake/provenance.h"
#include "crowd/formats/character_pack.h"
#include "crowd/formats/error.h"

namespace crowd {

using namespace jobs;

namespace {

using nlohmann::ordered_json;

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
  JobRun run(job, context);
  const CharacterManifest &m = run.m;
  Character body = importBody(m, run.reporter);
  Part part;
  auto &f = part.figures;
  f["input_triangles"] = body.mesh.indices.size() / 3;
  f["joints"] = body.jointCount();
  f["import_s"] = since(run.t0);
  AnimBakeResult anim;
  if (m.outfits.empty()) {
    std::optional<pack::Lod> lod;
    if (m.lod) {
      const auto t1 = Clock::now();
      LodResult details;
      lod = applyLod(body, m.lodOptions, run.reporter, &details);
      f["lod"] = lodFigures(*lod, f["input_triangles"], &details.colourChange);
      f["lod"]["time_s"] = since(t1);
    }
    AnimBakeOptions ao = m.anim;
    ao.threads = run.threads;
    anim = bakeAnimation(body, ao, run.reporter);
    anim.pack.lod = std::move(lod);
  } else {
    std::vector<OutfitInput> outfits;
    for (const auto &[name, file] : m.outfits)
      outfits.push_back({name, importFile(m, file, run.reporter), {}});
    addLoops(outfits, cloths);
    OutfitOptions oo = m.outfitOptions;
    oo.setAnimation(m.anim);
    oo.anim.threads = oo.visibility.threads = run.threads;
    if (m.lod)
      oo.lod = m.lodOptions;
    OutfitBakeResult r = bakeOutfits(body, outfits, oo, run.reporter);
    f.update(outfitFigures(r, oo));
    if (r.anim.pack.lod)
      f["lod"] = lodFigures(*r.anim.pack.lod, r.taggedFaces, &r.lodColourChange);
    anim = std::move(r.anim);
  }
  const auto &mesh = anim.pack.mesh;
  f["vertices"] = mesh.vertexCount();
  f["triangles"] = mesh.indices.size() / 3;
  f["sub_meshes"] = mesh.subMeshes.size();
  f.update(animFigures(anim));
  addChunks(part, pack::packBytes(anim.pack), false);
  run.finish(part);
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
