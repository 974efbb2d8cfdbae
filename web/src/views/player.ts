// #/jobs/ID/player: the finished job's animated glTF (result.glb, fetched with the key header)
// in three.js: play / pause / scrub, an orbit camera, a ground grid and the charges of the job's
// scene as small red spheres. This module and three.js form their own chunk.
import {
  AnimationMixer, Box3, LoopOnce, Color, DirectionalLight, GridHelper, HemisphereLight, type Material, Mesh,
  MeshStandardMaterial, type Object3D, PerspectiveCamera, PlaneGeometry, Scene as ThreeScene, SphereGeometry, Vector3,
  WebGLRenderer,
} from "three";
import { OrbitControls } from "three/addons/controls/OrbitControls.js";
import { type GLTF, GLTFLoader } from "three/addons/loaders/GLTFLoader.js";
import { client, describe, type Scene } from "../api";
import { h, mount } from "../dom";
import type { View } from "../view";

const parseGlb = (buffer: ArrayBuffer): Promise<GLTF> =>
  new Promise((resolve, reject) => new GLTFLoader().parse(buffer, "", resolve, reject));

/** A muted colour per body, so neighbouring pieces can be told apart. */
function tint(name: string): Color {
  let hash = 0;
  for (const c of name) hash = (hash * 31 + c.charCodeAt(0)) >>> 0;
  return new Color().setHSL((hash % 360) / 360, 0.35, 0.6);
}

export const playerView: View = async (root, route, signal) => {
  const id = route.id;
  const status = h("p", { class: "muted", id: "player-status" }, "Loading result.glb…");
  const stage = h("div", { class: "stage", id: "player-stage" });
  mount(root, h("p", null, h("a", { href: `#/jobs/${id}` }, "← Job ", h("code", null, id))),
        h("h1", null, "3D player"), status, stage);

  let gltf: GLTF, scene: Scene;
  try {
    const [glb, sceneJson] = await Promise.all([client.getGlb(id, { signal }), client.getScene(id, { signal })]);
    gltf = await parseGlb(glb);
    scene = sceneJson;
  } catch (error) {
    if (signal.aborted) return;
    status.className = "error";
    status.textContent = describe(error);
    return;
  }
  if (signal.aborted) return;

  // ---- the scene: the bodies, the charges, the ground grid, light
  const world = new ThreeScene();
  world.background = new Color(0x1d2733);
  world.add(new HemisphereLight(0xdde8ff, 0x3a3024, 1.4));
  const sun = new DirectionalLight(0xffffff, 2.2);
  sun.position.set(8, 14, 6);
  world.add(sun);

  world.add(gltf.scene);
  gltf.scene.traverse((node: Object3D) => {
    if (node instanceof Mesh) {
      const material = (node.material as Material).clone() as MeshStandardMaterial;
      if (material.color) material.color = tint(node.name || node.parent?.name || "");
      node.material = material;
    }
  });

  const bounds = new Box3().setFromObject(gltf.scene);
  const chargeMaterial = new MeshStandardMaterial({ color: 0xff2a1a, emissive: 0xa00000, roughness: 0.4 });
  for (const charge of scene.charges) {
    const radius = 0.06 + 0.05 * Math.cbrt(typeof charge.mass === "number" ? charge.mass : 1);
    const sphere = new Mesh(new SphereGeometry(radius, 24, 16), chargeMaterial);
    sphere.name = "charge";
    sphere.position.fromArray(charge.position);
    world.add(sphere);
    bounds.expandByPoint(sphere.position);
  }
  const ground = scene.environment?.ground;
  const groundY = ground === null ? bounds.min.y : (ground?.height ?? 0);
  const size = bounds.getSize(new Vector3());
  const centre = bounds.getCenter(new Vector3());
  const extent = Math.max(size.x, size.y, size.z, 1);
  // The ground: a plane a shade lighter than the sky, and a grid about four times the scene's
  // size in squares of 1, 10, 100 … m (or 0.1 m for a small scene).
  const step = 10 ** Math.round(Math.log10(extent / 5));
  const divisions = 2 * Math.ceil((2 * extent) / step);
  const gridSize = divisions * step;
  const plane = new Mesh(new PlaneGeometry(gridSize * 4, gridSize * 4),
                         new MeshStandardMaterial({ color: 0x2b3846, roughness: 1 }));
  plane.rotation.x = -Math.PI / 2;
  plane.position.set(centre.x, groundY - extent / 500, centre.z);
  world.add(plane);
  const grid = new GridHelper(gridSize, divisions, 0xc5d0dc, 0x71839a);
  grid.position.set(centre.x, groundY, centre.z);
  world.add(grid);

  // ---- renderer, camera, controls
  const renderer = new WebGLRenderer({ antialias: true });
  renderer.setPixelRatio(Math.min(window.devicePixelRatio, 2));
  const camera = new PerspectiveCamera(45, 16 / 9, extent / 100, extent * 100);
  camera.position.copy(centre).add(new Vector3(0.9, 0.55, 1.1).normalize().multiplyScalar(extent * 1.5));
  const controls = new OrbitControls(camera, renderer.domElement);
  controls.target.copy(centre);
  controls.enableDamping = true;
  controls.update();

  // ---- the animation: one clip "blast" of the moving bodies
  const mixer = new AnimationMixer(gltf.scene);
  // Played once and held at the end (a repeating loop would wrap the last frame back to 0).
  const actions = gltf.animations.map((clip) => {
    const action = mixer.clipAction(clip).setLoop(LoopOnce, 1);
    action.clampWhenFinished = true;
    return action;
  });
  const duration = Math.max(0, ...gltf.animations.map((clip) => clip.duration));
  let time = 0;
  let playing = duration > 0;
  const showTime = (t: number) => {
    time = Math.min(Math.max(t, 0), duration);
    for (const action of actions) action.reset().play();  // reset: a clamped finished action stays usable
    mixer.setTime(time);
    scrub.value = String(time);
    timeLabel.textContent = `${time.toFixed(3)} s / ${duration.toFixed(3)} s`;
  };

  const play = h("button", { type: "button", id: "play-pause", class: "primary", disabled: duration === 0,
                             onclick: () => { playing = !playing; if (playing && time >= duration) showTime(0); syncButton(); } });
  const syncButton = () => { play.textContent = playing ? "Pause" : "Play"; };
  const scrub = h("input", { id: "scrub", type: "range", min: 0, max: duration, step: "any", value: "0",
                             "aria-label": "Time", disabled: duration === 0,
                             oninput: () => { playing = false; syncButton(); showTime(Number(scrub.value)); } });
  const timeLabel = h("span", { class: "time", id: "time-label" });
  const speed = h("select", { id: "speed", "aria-label": "Speed" },
    [0.1, 0.25, 0.5, 1].map((v) => h("option", { value: v, selected: v === 0.25 }, `${v}×`)));
  syncButton();
  mount(stage, renderer.domElement,
    h("div", { class: "player-controls" }, play, scrub, timeLabel, speed));
  renderer.domElement.id = "player-canvas";
  const bodies = gltf.scene.children.length;
  status.textContent = `${bodies} bodies, ${scene.charges.length} charge(s) (red); ` +
    (duration > 0 ? `${duration.toFixed(2)} s of motion. Drag to orbit, scroll to zoom.` : "nothing moves.");
  showTime(0);

  const resize = () => {
    const width = stage.clientWidth || 800;
    const height = Math.round(Math.min(width * 9 / 16, window.innerHeight * 0.7));
    renderer.setSize(width, height);
    camera.aspect = width / height;
    camera.updateProjectionMatrix();
  };
  const observer = new ResizeObserver(resize);
  observer.observe(stage);
  resize();

  let last = performance.now();
  let frames = 0;
  const loop = (now: number) => {
    const dt = Math.min(0.1, (now - last) / 1000);
    last = now;
    if (playing) {
      const next = time + dt * Number(speed.value);
      showTime(next >= duration ? 0 : next);  // loops
    }
    controls.update();
    renderer.render(world, camera);
    if (++frames === 2) stage.dataset.state = "ready";  // drawn: the browser test waits on this
    handle = requestAnimationFrame(loop);
  };
  let handle = requestAnimationFrame(loop);

  signal.addEventListener("abort", () => {
    cancelAnimationFrame(handle);
    observer.disconnect();
    controls.dispose();
    mixer.stopAllAction();
    world.traverse((node: Object3D) => {
      if (node instanceof Mesh) {
        node.geometry.dispose();
        (node.material as Material).dispose();
      }
    });
    renderer.dispose();
  }, { once: true });
};
