// crowdbake export --gltf read by another tool: three.js (GLTFLoader, AnimationMixer) poses the
// exported file at 6 seeded random times per clip, and crowdbake pose draws the pack at the same
// times with the same outfit and LOD cut; vertex i of the export is pose's vertex i.
//
// node threejs_export.mjs CROWDBAKE THREE_DIR PACK GLB REPORT WORK [POSE_ARGS...]
// Prints a line per clip; exits 1 where three.js's pose is farther from crowdbake pose than its
// bound, or the file holds other clips than the pack. The bound: for joint tracks (exported as
// their own keys, which three.js interpolates as the palette pass does) 0.0032 mm, twice the
// 0.0016 mm docs/commands.md states (float rounding); for an animation texture (its frames'
// local transforms, which three.js slerps where the player blends dual quaternions) the pack's
// own max_error_any_time_mm (the report's; 0.01 mm at least).
import { execFileSync } from 'node:child_process';
import fs from 'node:fs';
import path from 'node:path';
import { pathToFileURL } from 'node:url';
import { modelJson, readPly, threePosition } from './threejs_gltf.mjs';

const [crowdbake, threeDir, pack, glb, reportPath, work, ...poseArgs] = process.argv.slice(2);
const THREE = await import(pathToFileURL(path.join(threeDir, 'build/three.module.js')));
const { GLTFLoader } = await import(
  pathToFileURL(path.join(threeDir, 'examples/jsm/loaders/GLTFLoader.js')));

const kTimes = 6;
const kFloorMm = 0.01;
const kTracksMm = 0.0032;
const json = modelJson(glb);
const gltf = await new Promise((resolve, reject) =>
  new GLTFLoader().parse(JSON.stringify(json), '', resolve, reject));
const skinned = [];
gltf.scene.traverse(o => { if (o.isSkinnedMesh) skinned.push(o); });
const report = JSON.parse(fs.readFileSync(reportPath, 'utf8'));
const names = gltf.animations.map(a => a.name).sort().join(',');
const expected = report.clips.map(c => c.name).sort().join(',');
if (names !== expected) {
  console.log(`FAIL: ${path.basename(glb)}: clips ${names}, the pack's ${expected}`);
  process.exit(1);
}
const mixer = new THREE.AnimationMixer(gltf.scene);
const v = new THREE.Vector3(), m = new THREE.Vector3();
let failed = false;
for (const [c, clip] of report.clips.entries()) {
  const action = mixer.clipAction(gltf.animations.find(a => a.name === clip.name));
  action.setLoop(THREE.LoopOnce);
  action.clampWhenFinished = true;
  const duration = (clip.frames - 1) / clip.fps;
  let state = BigInt(c + 1) * 0x9e3779b97f4a7c15n & ((1n << 64n) - 1n);
  const times = [];
  for (let k = 0; k < kTimes; ++k) {
    state = (state * 6364136223846793005n + 1442695040888963407n) & ((1n << 64n) - 1n);
    times.push(Number((Number(state >> 11n) / 2 ** 53 * duration).toPrecision(9)));
  }
  const stem = path.join(work, `${path.basename(glb, '.glb')}_${clip.name}`);
  execFileSync(crowdbake, ['pose', pack, '--clip', clip.name, '--times', times.join(','),
                           '-o', `${stem}.ply`, '-q', ...poseArgs]);
  let max = 0, sum = 0, count = 0;
  times.forEach((t, k) => {
    mixer.stopAllAction();
    action.reset().play();
    mixer.setTime(t);
    gltf.scene.updateMatrixWorld(true);
    for (const o of skinned) o.skeleton.update();
    const file = `${stem}_${String(k + 1).padStart(4, '0')}.ply`;
    const posed = readPly(file);
    const o = skinned[0];
    if (o.geometry.attributes.position.count !== posed.length)
      throw new Error(`${glb}: ${o.geometry.attributes.position.count} vertices, pose ${posed.length}`);
    posed.forEach((q, i) => {
      threePosition(o, i, v, m);
      const e = Math.hypot(v.x - q.p[0], v.y - q.p[1], v.z - q.p[2]) * report.mm_per_model_unit;
      max = Math.max(max, e), sum += e, ++count;
    });
    fs.unlinkSync(file);
  });
  const tracks = report.store === 'tracks';
  const bound = tracks ? kTracksMm : Math.max(kFloorMm, clip.max_error_any_time_mm);
  const miss = max > bound;
  failed ||= miss;
  console.log(`${miss ? 'FAIL' : 'ok'}: ${path.basename(glb)} '${clip.name}': three.js vs pose at ` +
              `${kTimes} random times: max ${max.toPrecision(3)} mm, mean ` +
              `${(sum / count).toPrecision(3)} mm (bound: ` +
              `${tracks ? 'float rounding of the tracks\' keys' : 'the pack\'s any-time error'}, ` +
              `${bound.toPrecision(3)} mm)`);
}
process.exit(failed ? 1 : 0);
