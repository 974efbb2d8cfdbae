// #/jobs/ID/player: the finished job's animated glTF (result.glb, fetched with the key header)
// in three.js: play / pause / scrub / step a frame, an orbit camera that frames the bodies that
// move (the whole scene with "Frame all") and follows the debris, the ground (a floor and a grid,
// only a grid when the scene has no ground) and the charges of the job's scene as small red
// spheres. Clicking a body shows its name, mass and speed. Thin fragments are drawn from both
// sides; broken panes' fragments can be coloured by their release time or their speed at the
// end, with a legend. This module and three.js form their own chunk.
import {
  AnimationMixer, Box3, LoopOnce, Color, Raycaster, Vector2, VectorKeyframeTrack, DirectionalLight, DoubleSide, GridHelper, HemisphereLight, type Material,
  Mesh, MeshStandardMaterial, type Object3D, PerspectiveCamera, PlaneGeometry, PropertyBinding, Scene as ThreeScene,
  SphereGeometry, Vector3, WebGLRenderer,
} from "three";
import { OrbitControls } from "three/addons/controls/OrbitControls.js";
import { type GLTF, GLTFLoader } from "three/addons/loaders/GLTFLoader.js";
import { client, describe, type ResultSummary, type Scene } from "../api";
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

/** Blue (low) through green to red (high), for t in [0, 1]. */
function ramp(t: number): Color {
  return new Color().setHSL((1 - Math.min(1, Math.max(0, t))) * 0.66, 0.75, 0.55);
}

type ColourMode = "material" | "body" | "release" | "speed";

/** Per body index, the value a colour mode shows (null: not shown, tinted by name). */
function valuesFor(mode: ColourMode, result: ResultSummary): (number | null)[] {
  const values: (number | null)[] = result.bodies.map(() => null);
  if (mode === "release") {
    for (const pane of result.fracture ?? [])
      pane.release_times_s.forEach((t, k) => { values[pane.first_body + k] = t ?? null; });
  } else if (mode === "speed") {
    result.final_state.forEach((state, b) => { values[b] = Math.hypot(...state.linear_velocity); });
  }
  return values;
}

export const playerView: View = async (root, route, signal) => {
  const id = route.id;
  const status = h("p", { class: "muted", id: "player-status" }, "Loading result.glb…");
  const stage = h("div", { class: "stage", id: "player-stage" });
  mount(root, h("p", null, h("a", { href: `#/jobs/${id}` }, "← Job ", h("code", null, id))),
        h("h1", null, "3D player"), status, stage);

  let gltf: GLTF, scene: Scene, result: ResultSummary;
  try {
    const [glb, sceneJson, summary] = await Promise.all([
      client.getGlb(id, { signal }), client.getScene(id, { signal }), client.getResult(id, { signal })]);
    gltf = await parseGlb(glb);
    scene = sceneJson;
    result = summary;
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
  // Each body's meshes, by the body's index in the result (glTF nodes carry the body names, as
  // the loader sanitises them: "window/pane/f3" becomes "window_pane_f3").
  const bodyIndex = new Map(result.bodies.map((body) => [PropertyBinding.sanitizeNodeName(body.name), body.index]));
  const meshesOf: Mesh[][] = result.bodies.map(() => []);
  // Each mesh's own look from the file (glass blends, crack faces are frostier), restored by the
  // "material" colour mode; the other modes paint opaque colours over it.
  const looks = new Map<MeshStandardMaterial, { color: Color; opacity: number; transparent: boolean }>();
  gltf.scene.traverse((node: Object3D) => {
    if (node instanceof Mesh) {
      const material = (node.material as Material).clone() as MeshStandardMaterial;
      material.side = DoubleSide;  // a 6 mm fragment seen edge-on or from behind is still drawn
      looks.set(material, { color: material.color.clone(), opacity: material.opacity, transparent: material.transparent });
      node.material = material;
      const index = bodyIndex.get(node.name) ?? bodyIndex.get(node.parent?.name ?? "");
      if (index !== undefined) meshesOf[index]?.push(node);
    }
  });
  const legend = h("div", { class: "legend", id: "player-legend", hidden: true });
  const colour = (mode: ColourMode) => {
    const values = valuesFor(mode, result);
    const shown = values.filter((v): v is number => v !== null);
    const low = Math.min(...shown), high = Math.max(...shown);
    meshesOf.forEach((meshes, b) => {
      const value = values[b] ?? null;
      const c = value === null ? tint(result.bodies[b]?.name ?? "")
        : ramp(high > low ? (value - low) / (high - low) : 0.5);
      for (const mesh of meshes) {
        const material = mesh.material as MeshStandardMaterial;
        const look = looks.get(material);
        const own = mode === "material" && look !== undefined;
        material.color = own ? look.color.clone() : c;
        material.opacity = own ? look.opacity : 1;
        material.transparent = own ? look.transparent : false;
        material.needsUpdate = true;
      }
    });
    if (mode === "body" || mode === "material" || shown.length === 0) {
      legend.hidden = true;
      return;
    }
    const label = mode === "release" ? "Release time" : "Speed at the end";
    const fmt = (v: number) => mode === "release" ? `${(v * 1e3).toFixed(2)} ms` : `${v.toFixed(2)} m/s`;
    mount(legend, h("span", null, label), h("span", { class: "legend-low" }, fmt(low)),
          h("span", { class: "legend-bar" }), h("span", { class: "legend-high" }, fmt(high)));
    legend.hidden = false;
  };
  const broken = (result.fracture ?? []).some((pane) => pane.broken);
  const colourBy = h("select", { id: "colour-by", "aria-label": "Colour by", onchange: () => colour(colourBy.value as ColourMode) },
    h("option", { value: "material" }, "Colour: material (as in the .glb)"),
    h("option", { value: "body", selected: !broken }, "Colour: by body"),
    h("option", { value: "release", selected: broken, disabled: !broken }, "Colour: fragment release time"),
    h("option", { value: "speed" }, "Colour: speed at the end"));
  colour(broken ? "release" : "body");

  // Everything at the start (bodies and charges) sizes the ground and the "Frame all" view.
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
  // Without a ground in the scene there is no floor to hide what falls: only the grid, below
  // everything, as a reference.
  stage.dataset.floor = ground === null ? "none" : "plane";
  if (ground !== null) {
    const plane = new Mesh(new PlaneGeometry(gridSize * 4, gridSize * 4),
                           new MeshStandardMaterial({ color: 0x2b3846, roughness: 1 }));
    plane.name = "floor";
    plane.rotation.x = -Math.PI / 2;
    plane.position.set(centre.x, groundY - extent / 500, centre.z);
    world.add(plane);
  }
  const grid = new GridHelper(gridSize, divisions, 0xc5d0dc, 0x71839a);
  grid.position.set(centre.x, groundY, centre.z);
  world.add(grid);

  // ---- renderer, camera, controls
  const renderer = new WebGLRenderer({ antialias: true });
  renderer.setPixelRatio(Math.min(window.devicePixelRatio, 2));
  const camera = new PerspectiveCamera(45, 16 / 9, extent / 1000, extent * 100);
  const controls = new OrbitControls(camera, renderer.domElement);
  controls.enableDamping = true;
  // Looks at `box` from the usual three-quarter view, far enough to see all of it.
  const frameBox = (box: Box3) => {
    const boxCentre = box.getCenter(new Vector3());
    const boxSize = box.getSize(new Vector3());
    const reach = Math.max(boxSize.x, boxSize.y, boxSize.z, extent / 200, 0.05);
    camera.position.copy(boxCentre).add(new Vector3(0.9, 0.55, 1.1).normalize().multiplyScalar(reach * 1.6));
    controls.target.copy(boxCentre);
    controls.update();
  };

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
  let refreshInfo = (): void => {};  // the clicked body's panel, once there is one
  const showTime = (t: number) => {
    time = Math.min(Math.max(t, 0), duration);
    for (const action of actions) action.reset().play();  // reset: a clamped finished action stays usable
    mixer.setTime(time);
    scrub.value = String(time);
    timeLabel.textContent = `${time.toFixed(3)} s / ${duration.toFixed(3)} s`;
    stage.dataset.time = String(time);
    refreshInfo();
  };

  const play = h("button", { type: "button", id: "play-pause", class: "primary", disabled: duration === 0,
                             onclick: () => { playing = !playing; if (playing && time >= duration) showTime(0); syncButton(); } });
  const syncButton = () => { play.textContent = playing ? "Pause" : "Play"; };
  const scrub = h("input", { id: "scrub", type: "range", min: 0, max: duration, step: "any", value: "0",
                             "aria-label": "Time", disabled: duration === 0,
                             oninput: () => { playing = false; syncButton(); showTime(Number(scrub.value)); } });
  const timeLabel = h("span", { class: "time", id: "time-label" });
  // One stored frame: the result's frames are equally spaced from 0 to the duration.
  const frameStep = result.frame_count > 1 ? duration / (result.frame_count - 1) : 0;
  const stepBy = (frames: number) => {
    playing = false;
    syncButton();
    showTime(Math.round(time / frameStep + frames) * frameStep);
  };
  const back = h("button", { type: "button", id: "step-back", title: "One frame back (,)", disabled: duration === 0,
                             onclick: () => stepBy(-1) }, "◀");
  const forward = h("button", { type: "button", id: "step-forward", title: "One frame on (.)", disabled: duration === 0,
                                onclick: () => stepBy(1) }, "▶");
  const onKey = (e: KeyboardEvent) => {
    if (e.target instanceof HTMLInputElement || e.target instanceof HTMLSelectElement) return;
    if (e.key === "," || e.key === ".") stepBy(e.key === "," ? -1 : 1);
  };
  if (frameStep > 0) window.addEventListener("keydown", onKey);
  const speed = h("select", { id: "speed", "aria-label": "Speed" },
    [0.1, 0.25, 0.5, 1].map((v) => h("option", { value: v, selected: v === 0.25 }, `${v}×`)));
  const follow = h("input", { type: "checkbox", id: "follow-debris", checked: duration > 0 });
  const frameAll = h("button", { type: "button", id: "frame-all", title: "Show every body and charge",
                                 onclick: () => { follow.checked = false; frameBox(bounds); } }, "Frame all");
  const info = h("div", { class: "body-info", id: "body-info", hidden: true, role: "status" });
  syncButton();
  mount(stage, renderer.domElement,
    h("div", { class: "player-controls" }, play, back, forward, scrub, timeLabel, speed, colourBy,
      h("label", null, follow, " Follow the debris"), frameAll),
    legend, info);
  renderer.domElement.id = "player-canvas";
  const bodies = gltf.scene.children.length;
  status.textContent = `${bodies} bodies, ${scene.charges.length} charge(s) (red); ` +
    (duration > 0 ? `${duration.toFixed(2)} s of motion. Drag to orbit, scroll to zoom.` : "nothing moves.");
  // The first view: the bodies that move, over the whole run (where they start and where they
  // end), not a charge many metres away; the whole scene when nothing moves.
  const moving = result.animated.flatMap((b) => meshesOf[b] ?? []);
  const movingBox = (): Box3 => {
    const box = new Box3();
    for (const mesh of moving) box.expandByObject(mesh);
    return box;
  };
  if (moving.length > 0 && duration > 0) {
    showTime(duration);
    const box = movingBox();
    showTime(0);
    box.union(movingBox());
    frameBox(box);
    // Without a ground, the reference grid goes below everything the run shows, not across it.
    if (ground === null) grid.position.y = Math.min(grid.position.y, box.min.y);
  } else {
    frameBox(bounds);
  }
  showTime(0);

  // Clicking a body: its name, mass and speed at this time (from the animation's translation
  // samples, which follow its centre of mass) and at the end of the run.
  const bodyOfMesh = new Map<Object3D, number>();
  meshesOf.forEach((meshes, b) => meshes.forEach((mesh) => bodyOfMesh.set(mesh, b)));
  const tracks = new Map<string, VectorKeyframeTrack>();
  for (const clip of gltf.animations)
    for (const track of clip.tracks)
      if (track.name.endsWith(".position") && track instanceof VectorKeyframeTrack)
        tracks.set(track.name.slice(0, -".position".length), track);
  const speedAt = (b: number, t: number): number => {
    const track = tracks.get(PropertyBinding.sanitizeNodeName(result.bodies[b]?.name ?? ""));
    if (!track || track.times.length < 2) return 0;
    let i = 0;
    while (i < track.times.length - 2 && (track.times[i + 1] ?? 0) <= t) i++;
    const dt = (track.times[i + 1] ?? 0) - (track.times[i] ?? 0);
    if (!(dt > 0)) return 0;
    const v = [0, 1, 2].map((c) => ((track.values[3 * (i + 1) + c] ?? 0) - (track.values[3 * i + c] ?? 0)) / dt);
    return Math.hypot(...v);
  };
  let picked: number | null = null;
  const showInfo = () => {
    if (picked === null) { info.hidden = true; return; }
    const body = result.bodies[picked];
    const end = result.final_state[picked];
    if (!body) return;
    mount(info, h("strong", { class: "body-name" }, body.name),
      h("span", null, `mass ${body.mass.toPrecision(3)} kg`),
      h("span", { class: "body-speed" }, body.animated
        ? `${speedAt(picked, time).toFixed(2)} m/s over the frame from ${time.toFixed(3)} s` : "does not move"),
      end && body.animated ? h("span", null, `${Math.hypot(...end.linear_velocity).toFixed(2)} m/s at the end`) : null);
    info.hidden = false;
  };
  refreshInfo = showInfo;
  const raycaster = new Raycaster();
  let pressedAt: [number, number] | null = null;
  renderer.domElement.addEventListener("pointerdown", (e) => { pressedAt = [e.clientX, e.clientY]; });
  renderer.domElement.addEventListener("pointerup", (e) => {
    // A click, not the end of an orbit drag.
    if (!pressedAt || Math.hypot(e.clientX - pressedAt[0], e.clientY - pressedAt[1]) > 4) return;
    const rect = renderer.domElement.getBoundingClientRect();
    raycaster.setFromCamera(new Vector2(((e.clientX - rect.left) / rect.width) * 2 - 1,
                                        -((e.clientY - rect.top) / rect.height) * 2 + 1), camera);
    const hit = raycaster.intersectObjects([...bodyOfMesh.keys()], false)[0];
    picked = hit ? bodyOfMesh.get(hit.object) ?? null : null;
    showInfo();
  });

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

  // Following the debris: the view's target eases towards the centre of the bodies that move,
  // and the camera keeps its offset from the target (the user still orbits and zooms).
  const movingBounds = new Box3();
  const movingCentre = new Vector3();
  const followDebris = () => {
    if (!follow.checked || moving.length === 0) return;
    movingBounds.makeEmpty();
    for (const mesh of moving) movingBounds.expandByObject(mesh);
    if (movingBounds.isEmpty()) return;
    movingBounds.getCenter(movingCentre);
    const shift = movingCentre.sub(controls.target).multiplyScalar(0.1);
    controls.target.add(shift);
    camera.position.add(shift);
  };

  let last = performance.now();
  let frames = 0;
  const loop = (now: number) => {
    const dt = Math.min(0.1, (now - last) / 1000);
    last = now;
    if (playing) {
      const next = time + dt * Number(speed.value);
      showTime(next >= duration ? 0 : next);  // loops
    }
    followDebris();
    controls.update();
    renderer.render(world, camera);
    if (++frames === 2) stage.dataset.state = "ready";  // drawn: the browser test waits on this
    handle = requestAnimationFrame(loop);
  };
  let handle = requestAnimationFrame(loop);

  signal.addEventListener("abort", () => {
    cancelAnimationFrame(handle);
    window.removeEventListener("keydown", onKey);
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
