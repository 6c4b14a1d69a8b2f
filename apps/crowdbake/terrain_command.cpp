// crowdbake terrain: an environment glTF into the maps a crowd walks on and is shaded by.
#include <sstream>

#include "args.h"
#include "commands.h"
#include "crowd/bake/terrain_bake.h"

namespace crowd::cli {

namespace {

const char *const kTerrainDescription =
    R"(Rasterizes the environment's meshes (every mesh of the glTF,
placed by its nodes) from straight above into a grid of --cell sized cells, as Tecchia, Loscos &
Chrysanthou do: the height map holds each cell's top surface; the walkable map marks
the cells no steeper than --max-slope that agents reach from the largest such area by steps of
at most --step (other flat cells, such as roofs, are blocked and reported); the shadow height
map gives, per cell, the height below which a point is in the shadow of the environment for the
directional light --light (towards the light, §4.5). The pack holds one TERR chunk (the three
maps and the environment's mesh for drawing); 'crowdbake export --images' writes the maps.)";

glm::dvec3 parseLight(const std::string &text) {
  std::istringstream in(text);
  glm::dvec3 v(0);
  char comma1 = 0, comma2 = 0;
  if (!(in >> v.x >> comma1 >> v.y >> comma2 >> v.z) || comma1 != ',' || comma2 != ',' ||
      !(in >> std::ws).eof())
    throw UsageError("--light expects X,Y,Z (a direction towards the light), got '" + text + "'");
  return v;
}

} // namespace

int cmdTerrain(int argc, char **argv) {
  CLI::App app(kTerrainDescription, "crowdbake terrain");
  example(app, "crowdbake terrain village.glb -o village.crowdpack --cell 0.25 --light 0.4,1,0.3 "
               "--report village.json");
  BakeArgs b;
  b.add(app, "the environment (.glb or .gltf)");
  TerrainOptions o;
  std::string light = "0.4,1,0.3";
  app.add_option("--cell", o.cell, "a cell's side, in model units (metres)")->capture_default_str();
  app.add_option("--light", light, "X,Y,Z: the direction towards the light (Y > 0)")
      ->capture_default_str();
  app.add_option("--step", o.stepHeight, "the highest step an agent climbs or descends")
      ->capture_default_str();
  app.add_option("--max-slope", o.maxSlopeDeg, "the steepest surface an agent stands on (deg)")
      ->capture_default_str();
  addThreads(app, o.threads);
  if (!parseArgs(app, argc, argv))
    return 0;
  b.files.finish();
  o.light = parseLight(light);
  validated(o);
  CharacterManifest m = b.manifest();
  m.terrain = o;
  m.lod = false;
  b.runJob(m, "terrain", "terrain", o.threads);
  return 0;
}

} // namespace crowd::cli
