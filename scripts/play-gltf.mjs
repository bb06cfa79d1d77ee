// Play a .glb with three.js as a viewer does (GLTFLoader with three's meshopt decoder, so
// EXT_meshopt_compression files play too; AnimationMixer with the default looping action)
// at the given times; prints one JSON object: for every node name, its local position,
// quaternion (x, y, z, w) and scale at each time, or with --world the same three taken from
// its world matrix (node.matrixWorld: every parent's transform applied, the root's too).
// Usage: node scripts/play-gltf.mjs FILE.glb TIMES.json [--world]
import { readFile } from "node:fs/promises";
import { AnimationMixer, Quaternion, Vector3 } from "three";
import { GLTFLoader } from "three/addons/loaders/GLTFLoader.js";
import { MeshoptDecoder } from "three/addons/libs/meshopt_decoder.module.js";

globalThis.navigator ??= { userAgent: "node" };   // GLTFLoader reads it; node 20 has none
const [file, timesFile, ...flags] = process.argv.slice(2);
const world = flags.includes("--world");
const bytes = await readFile(file);
const times = JSON.parse(await readFile(timesFile, "utf8"));
await MeshoptDecoder.ready;
const loader = new GLTFLoader().setMeshoptDecoder(MeshoptDecoder);
const gltf = await loader.parseAsync(bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.length), "");
const mixer = new AnimationMixer(gltf.scene);
for (const clip of gltf.animations) mixer.clipAction(clip).play();
// keyed by the file's node names (three.js sanitises its own: no ':' or '.')
const names = new Map();
gltf.scene.traverse((o) => {
  const index = gltf.parser.associations.get(o)?.nodes;
  if (index !== undefined && gltf.parser.json.nodes[index].name) names.set(o, gltf.parser.json.nodes[index].name);
});
const nodes = [...names.keys()];
const out = Object.fromEntries(nodes.map((o) => [names.get(o), { position: [], quaternion: [], scale: [] }]));
const [position, quaternion, scale] = [new Vector3(), new Quaternion(), new Vector3()];
for (const t of times) {
  mixer.setTime(t);
  if (world) gltf.scene.updateMatrixWorld(true);
  for (const o of nodes) {
    const node = out[names.get(o)];
    if (world) o.matrixWorld.decompose(position, quaternion, scale);
    node.position.push((world ? position : o.position).toArray());
    node.quaternion.push((world ? quaternion : o.quaternion).toArray());
    node.scale.push((world ? scale : o.scale).toArray());
  }
}
console.log(JSON.stringify(out));
