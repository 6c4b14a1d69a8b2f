// What the three.js harnesses share: a glTF as JSON three.js's GLTFLoader parses in node, and
// the binary PLY crowdbake pose writes.
import fs from 'node:fs';
import path from 'node:path';

// FileLoader (reading the data: URIs through fetch) reports progress with a DOM event.
globalThis.ProgressEvent ??= class extends Event {
  constructor(type, init) { super(type); Object.assign(this, init); }
};

// Textures need a DOM that node lacks: the JSON loses its images, textures and texture refs
// (they do not move vertices). External buffers become data: URIs, which node's fetch reads.
export function modelJson(file) {
  const data = fs.readFileSync(file);
  let json, bin = null;
  if (data.toString('latin1', 0, 4) === 'glTF') {
    const n = data.readUInt32LE(12);
    json = JSON.parse(data.toString('utf8', 20, 20 + n));
    if (data.length > 28 + n) bin = data.subarray(28 + n, 28 + n + data.readUInt32LE(20 + n));
  } else {
    json = JSON.parse(data.toString('utf8'));
  }
  delete json.images; delete json.textures; delete json.samplers;
  for (const m of json.materials || []) {
    const p = m.pbrMetallicRoughness || {};
    delete p.baseColorTexture; delete p.metallicRoughnessTexture;
    delete m.normalTexture; delete m.occlusionTexture; delete m.emissiveTexture;
  }
  for (const b of json.buffers || []) {
    if (b.uri === undefined) {
      b.uri = 'data:application/octet-stream;base64,' + bin.toString('base64');
    } else if (!b.uri.startsWith('data:')) {
      const bytes = fs.readFileSync(path.join(path.dirname(file), decodeURIComponent(b.uri)));
      b.uri = 'data:application/octet-stream;base64,' + bytes.toString('base64');
    }
  }
  return json;
}

// Binary PLY of crowdbake pose: x y z nx ny nz (float), source_file .. source_vertex (int).
export function readPly(file) {
  const data = fs.readFileSync(file);
  const end = data.indexOf('end_header\n') + 'end_header\n'.length;
  const count = Number(/element vertex (\d+)/.exec(data.toString('latin1', 0, end))[1]);
  const out = [];
  for (let i = 0, at = end; i < count; ++i, at += 44)
    out.push({ p: [data.readFloatLE(at), data.readFloatLE(at + 4), data.readFloatLE(at + 8)],
               node: data.readInt32LE(at + 28), mesh: data.readInt32LE(at + 32),
               primitive: data.readInt32LE(at + 36), vertex: data.readInt32LE(at + 40) });
  return out;
}


// Where three.js draws vertex `i` of `o` (into `v`, `m` a scratch THREE.Vector3): morph targets,
// skinning, then the mesh's world matrix.
export function threePosition(o, i, v, m) {
  v.fromBufferAttribute(o.geometry.attributes.position, i);
  const morphs = o.geometry.morphAttributes.position;
  if (morphs && o.morphTargetInfluences)
    morphs.forEach((attr, k) => v.addScaledVector(m.fromBufferAttribute(attr, i),
                                                  o.morphTargetInfluences[k]));
  if (o.isSkinnedMesh) o.applyBoneTransform(i, v);
  return v.applyMatrix4(o.matrixWorld);
}
