// Loads .glb files the way a three.js viewer does (GLTFLoader) and checks what a player needs:
// one node per body, one animation clip "blast" with a position and a quaternion track for
// every animated body, sampled at increasing times. Usage: node load_in_three.mjs FILE.glb
// [EXPECTED_NODES EXPECTED_ANIMATED_BODIES]; exits non-zero on any failure.
import { readFileSync } from "node:fs";
import { GLTFLoader } from "three/examples/jsm/loaders/GLTFLoader.js";

const [file, expectedNodes, expectedAnimated] = process.argv.slice(2);
if (!file) {
  console.error("usage: node load_in_three.mjs FILE.glb [EXPECTED_NODES EXPECTED_ANIMATED]");
  process.exit(2);
}
const bytes = readFileSync(file);
const buffer = bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.byteLength);

const loader = new GLTFLoader();
loader.parse(
  buffer,
  "",
  (gltf) => {
    const failures = [];
    const meshes = [];
    gltf.scene.traverse((o) => { if (o.isMesh) meshes.push(o); });
    if (expectedNodes !== undefined && meshes.length !== Number(expectedNodes))
      failures.push(`${meshes.length} meshes in the scene, expected ${expectedNodes}`);
    const clip = gltf.animations.find((a) => a.name === "blast");
    const animated = expectedAnimated === undefined ? undefined : Number(expectedAnimated);
    if (animated > 0) {
      if (!clip) {
        failures.push("no animation clip named 'blast'");
      } else {
        const positions = clip.tracks.filter((t) => t.name.endsWith(".position"));
        const rotations = clip.tracks.filter((t) => t.name.endsWith(".quaternion"));
        if (positions.length !== animated || rotations.length !== animated)
          failures.push(`${positions.length} position / ${rotations.length} quaternion tracks, expected ${animated} each`);
        for (const track of clip.tracks) {
          for (let i = 1; i < track.times.length; ++i)
            if (!(track.times[i] > track.times[i - 1])) { failures.push(`${track.name}: times not increasing`); break; }
          if (track.values.some((v) => !Number.isFinite(v))) failures.push(`${track.name}: non-finite values`);
        }
        if (!(clip.duration > 0)) failures.push(`clip duration ${clip.duration}`);
      }
    }
    if (failures.length) {
      console.error(`${file}: ${failures.join("; ")}`);
      process.exit(1);
    }
    console.log(`${file}: three.js loaded ${meshes.length} meshes` +
                (clip ? `, clip '${clip.name}' of ${clip.duration.toFixed(3)} s with ${clip.tracks.length} tracks` : ""));
  },
  (error) => {
    console.error(`${file}: three.js could not load it: ${error.message || error}`);
    process.exit(1);
  },
);
