// The independent reading: three.js (npm `three`, its GLTFLoader and AnimationMixer) poses a glTF
// at the times crowdbake pose draws its pack, and the two are compared vertex by vertex through
// the pack's vertex sources (PLY source_node, source_mesh, source_primitive, source_vertex).
//
// node threejs_pose.mjs CROWDBAKE THREE_DIR MODEL PACK REPORT WORK
// Prints one line per clip and writes WORK/<pack>.threejs.json; exits 1 where a clip misses the
// frame-time target (0.01 mm beyond the report's own frame-time error: the pack's rounding) or
// three.js's any-time error is not the report's max_error_any_time_mm.
import { execFileSync } from 'node:child_process';
import fs from 'node:fs';
import path from 'node:path';
import { pathToFileURL } from 'node:url';
import { modelJson, readPly, threePosition } from './threejs_gltf.mjs';

const [crowdbake, threeDir, model, pack, reportPath, work] = process.argv.slice(2);
const THREE = await import(pathToFileURL(path.join(threeDir, 'build/three.module.js')));
const { GLTFLoader } = await import(
  pathToFileURL(path.join(threeDir, 'examples/jsm/loaders/GLTFLoader.js')));
// gltfpack -c / -cc copies: three.js decodes their views with meshoptimizer's own JS decoder.
const { MeshoptDecoder } = await import(
  pathToFileURL(path.join(threeDir, 'examples/jsm/libs/meshopt_decoder.module.js')));

const kFrameTargetMm = 0.01; // agreement at frame times, at a 1.8 m character
const kRandomTimes = 64;     // per clip: the bake's kRandomTimesPerClip

const json = modelJson(model);
const gltf = await new Promise((resolve, reject) =>
  new GLTFLoader().setMeshoptDecoder(MeshoptDecoder).parse(JSON.stringify(json), '', resolve, reject));
// Each primitive's three.js mesh, by "node/mesh/primitive": a node's object is the mesh of a
// one-primitive mesh, else a group of them. (Instances of one mesh share one associations
// entry, whose node is the last instance's, so nodes are asked for by index.)
const meshes = new Map();
for (const [node, def] of (json.nodes || []).entries()) {
  if (def.mesh === undefined) continue;
  const object = await gltf.parser.getDependency('node', node);
  for (const o of object.isMesh ? [object] : object.children.filter(c => c.isMesh))
    meshes.set(`${node}/${def.mesh}/${gltf.parser.associations.get(o).primitives}`, o);
}
const report = JSON.parse(fs.readFileSync(reportPath, 'utf8'));
const mixer = new THREE.AnimationMixer(gltf.scene);
const v = new THREE.Vector3(), m = new THREE.Vector3();


let failed = false;
const summary = [];
for (const clip of report.clips) {
  // The pack names an unnamed glTF animation "clipN"; a "rest" clip with no animation is the
  // rest pose (a file without animations, or whose animations move no node).
  const index = (json.animations || []).findIndex((a, k) => (a.name || `clip${k}`) === clip.name);
  const source = index >= 0 ? gltf.animations[index] : null;
  const action = source ? mixer.clipAction(source) : null;
  if (action) { action.setLoop(THREE.LoopOnce); action.clampWhenFinished = true; }
  // Times: every frame, every mid-frame, and seeded random times over the clip.
  const duration = (clip.frames - 1) / clip.fps;
  const times = [], kinds = [];
  for (let k = 0; k < clip.frames; ++k) { times.push(k / clip.fps); kinds.push('frames'); }
  for (let k = 0; k + 1 < clip.frames; ++k) { times.push((k + 0.5) / clip.fps); kinds.push('midframes'); }
  // The bake's own random times (anim_bake.cpp: its seed per clip, PCG's LCG step), so that
  // three.js and the report measure the same instants.
  let state = (0x9e3779b97f4a7c15n * BigInt(report.clips.indexOf(clip) + 1)) & ((1n << 64n) - 1n);
  for (let k = 0; k < kRandomTimes && clip.frames > 1; ++k) {
    state = (state * 6364136223846793005n + 1442695040888963407n) & ((1n << 64n) - 1n);
    times.push(Number(state >> 11n) / 2 ** 53 * duration); kinds.push('random');
  }
  const stem = path.join(work, `${path.basename(pack, '.crowdpack')}_${clip.name}`);
  execFileSync(crowdbake, ['pose', pack, '--clip', clip.name, '--times',
                           times.map(t => t.toPrecision(9)).join(','), '-o', `${stem}.ply`, '-q']);
  // three.js keys its clip at the source times: the pack's t is start_time + t there. The
  // clip's first key, read from three.js's own tracks (not the pack's rounded start_time).
  const start = source ? Math.min(...source.tracks.map(t => t.times[0])) : 0;
  // The specification's rotations are unit quaternions; three.js composes a key as it is (a
  // scaled matrix) and slerps between keys as they are. Where keys are off unit length (gltfpack
  // quantizes them to 16 bits), three.js's LINEAR and STEP keys are normalized, as the importer
  // normalizes them (off by more than 1e-6), and its pose too (a CUBICSPLINE track's values hold
  // tangents), and it is named.
  let unitLength = 0;
  for (const track of source ? source.tracks : [])
    if (track.name.endsWith('.quaternion')) {
      const cubic = track.createInterpolant.isInterpolantFactoryMethodGLTFCubicSpline === true;
      for (let i = 0; i < track.values.length; i += 4) {
        const n = Math.hypot(...track.values.slice(i, i + 4));
        unitLength = Math.max(unitLength, Math.abs(n - 1));
        if (!cubic && Math.abs(n - 1) > 1e-6) for (let c = 0; c < 4; ++c) track.values[i + c] /= n;
      }
    }
  const max = { frames: 0, midframes: 0, random: 0 }, sum = { frames: 0, midframes: 0, random: 0 };
  const counted = { frames: 0, midframes: 0, random: 0 };
  let compared = 0;
  times.forEach((t, k) => {
    mixer.stopAllAction(); // one clip at a time, from its start
    if (action) { action.reset().play(); mixer.setTime(start + Number(t.toPrecision(9))); }
    if (unitLength > 1e-6) gltf.scene.traverse(o => o.quaternion.normalize());
    gltf.scene.updateMatrixWorld(true);
    for (const o of meshes.values()) if (o.isSkinnedMesh) o.skeleton.update();
    const file = times.length === 1 ? `${stem}.ply` : `${stem}_${String(k + 1).padStart(4, '0')}.ply`;
    for (const q of readPly(file)) {
      const o = meshes.get(`${q.node}/${q.mesh}/${q.primitive}`);
      if (!o) throw new Error(`${model}: no three.js mesh for node ${q.node}, mesh ${q.mesh}, primitive ${q.primitive}`);
      const w = threePosition(o, q.vertex, v, m);
      const e = Math.hypot(w.x - q.p[0], w.y - q.p[1], w.z - q.p[2]) * report.mm_per_model_unit;
      max[kinds[k]] = Math.max(max[kinds[k]], e);
      sum[kinds[k]] += e; ++counted[kinds[k]]; ++compared;
    }
    fs.unlinkSync(file);
  });
  const anyTime = Math.max(max.frames, max.midframes, max.random);
  const row = { model: path.basename(model), clip: clip.name, vertices_compared: compared,
                max_mm_at_frames: max.frames, max_mm_at_midframes: max.midframes,
                max_mm_at_random_times: max.random, max_mm_any_time: anyTime,
                mean_mm_at_random_times: counted.random ? sum.random / counted.random : 0,
                report_max_error_any_time_mm: clip.max_error_any_time_mm,
                ratio_to_report: clip.max_error_any_time_mm > 0 ? anyTime / clip.max_error_any_time_mm : null,
                known: [unitLength > 1e-6 ? `rotation keys up to ${unitLength.toPrecision(2)} off unit length: ` +
                          'normalized in three.js, which composes them as they are' : '']
                         .filter(Boolean).join('; ') };
  summary.push(row);
  // Between frames both readings see the same error (the pack's blend against the source): the
  // report's any-time figure must be three.js's within 5% (or 0.01 mm where both are tiny).
  // At frame times a pack stores its own error, which three.js must see as the report does
  // (within 5%): a compact precision's, and a float pack's float32 rounding (some 1e-4 mm, but
  // 0.008 mm on gltfpack's trooper, whose 14-bit positions reach 16383 under joint matrices
  // that move them by 76.5: float32 skinning of the file's own numbers, on any GPU too).
  // A pack of joint tracks (report.store "tracks") is measured at its own samples, between them
  // and at the same 64 random times: those must agree as above, and nothing three.js sees at the
  // texture frames' times may pass the report's any-time figure.
  const tracks = report.store === 'tracks';
  const close = (a, b) => Math.abs(a - b) <= kFrameTargetMm || Math.abs(a - b) <= 0.05 * b;
  const frameTarget = tracks
    ? kFrameTargetMm + 1.05 * clip.max_error_any_time_mm
    : kFrameTargetMm + 1.05 * clip.max_error_at_frames_model_units * report.mm_per_model_unit;
  const miss = tracks
    ? anyTime > frameTarget ||
      (counted.random > 0 && !close(max.random, clip.tracks.max_error_at_random_times_mm))
    : max.frames > frameTarget || !close(anyTime, clip.max_error_any_time_mm);
  failed ||= miss;
  console.log(`${miss ? 'FAIL' : 'ok'}: ${row.model} '${clip.name}': three.js vs pose, max ` +
              `${max.frames.toPrecision(3)} mm at ${clip.frames} frames (target ${frameTarget.toPrecision(3)}, ` +
              `${tracks ? 'tracks' : report.precision}), ` +
              `${max.midframes.toPrecision(3)} mm at mid-frames, ${max.random.toPrecision(3)} mm at ` +
              `${counted.random ? kRandomTimes : 0} random times; the report's any-time max ` +
              `${clip.max_error_any_time_mm.toPrecision(3)} mm, three.js's ${anyTime.toPrecision(3)} mm` +
              (row.known ? ` (known: ${row.known})` : ''));
}
// glTF animations the pack has no clip for, named with what they animate.
(json.animations || []).forEach((a, k) => {
  const name = a.name || `clip${k}`;
  if (report.clips.some(c => c.name === name)) return;
  const paths = [...new Set(a.channels.map(c => c.target.path))].join(', ');
  console.log(`note: ${path.basename(model)}: animation '${name}' (${paths}) has no clip in the pack`);
});
fs.writeFileSync(path.join(work, `${path.basename(pack, '.crowdpack')}.threejs.json`),
                 JSON.stringify(summary, null, 1));
process.exit(failed ? 1 : 0);
