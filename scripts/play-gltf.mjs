// Play a .glb with three.js as a viewer does (GLTFLoader, AnimationMixer with the default
// looping action) at the given times; prints one JSON object: for every node name, its
// local position, quaternion (x, y, z, w) and scale at each time.
// Usage: node scripts/play-gltf.mjs FILE.glb TIMES.json
import { readFile } from "node:fs/promises";
import { AnimationMixer } from "three";
import { GLTFLoader } from "three/addons/loaders/GLTFLoader.js";

globalThis.navigator ??= { userAgent: "node" };   // GLTFLoader reads it; node 20 has none
const [file, timesFile] = process.argv.slice(2);
const bytes = await readFile(file);
const times = JSON.parse(await readFile(timesFile, "utf8"));
const gltf = await new GLTFLoader().parseAsync(bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.length), "");
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
for (const t of times) {
  mixer.setTime(t);
  for (const o of nodes) {
    const node = out[names.get(o)];
    node.position.push(o.position.toArray());
    node.quaternion.push(o.quaternion.toArray());
    node.scale.push(o.scale.toArray());
  }
}
console.log(JSON.stringify(out));
