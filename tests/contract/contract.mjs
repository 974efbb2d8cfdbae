#!/usr/bin/env node
// The API contract test (CTest contract.api): starts real `brisance serve` processes, drives every
// endpoint of api/openapi.yaml and every status code it can provoke, and checks each response
// against the spec - status documented for the operation, Content-Type one of its media types,
// every required header present, every header (documented or not) checked, and the body
// validated with Ajv (JSON Schema 2020-12) or, for binary bodies, parsed by the layout the spec
// gives. It also checks that the Scene schema agrees with the server's validation on a set of
// valid and invalid scenes. Exits 0 when every check passed, 1 on any failure, 2 when it cannot
// run (missing packages, no binary).
//
//   node contract.mjs PATH/TO/brisance          (npm ci --prefix tests/contract first)
import { execFileSync } from "node:child_process";
import fs from "node:fs";
import http from "node:http";
import net from "node:net";
import os from "node:os";
import path from "node:path";
import { fileURLToPath } from "node:url";

import { startServer as startBrisance, stopServer as stopBrisance } from "../support/serve.mjs";

const here = path.dirname(fileURLToPath(import.meta.url));
const root = path.resolve(here, "../..");
const specPath = path.join(root, "api", "openapi.yaml");

let Ajv2020, addFormats, YAML;
try {
  Ajv2020 = (await import("ajv/dist/2020.js")).default;
  addFormats = (await import("ajv-formats")).default;
  YAML = (await import("yaml")).default;
} catch (error) {
  console.error(`contract.api cannot run: ${error.message}\n` +
                "Install the test's packages: `npm ci --prefix tests/contract` from the repository root.");
  process.exit(2);
}

const binary = process.argv[2];
if (!binary || !fs.existsSync(binary)) {
  console.error("usage: node contract.mjs PATH/TO/brisance (the binary was not found: " + binary + ")");
  process.exit(2);
}

// ------------------------------------------------------------------------------------------
// Bookkeeping

let checks = 0;
const failures = [];
const covered = new Map();  // "METHOD /path/template STATUS" -> count

function expect(condition, message) {
  checks++;
  if (!condition) {
    failures.push(message);
    console.log(`  FAIL ${message}`);
  }
  return condition;
}

const startedAt = Date.now();
function section(name) {
  console.log(`\n== ${name} (at ${((Date.now() - startedAt) / 1000).toFixed(1)} s)`);
}

// ------------------------------------------------------------------------------------------
// The spec and its schemas

const specText = fs.readFileSync(specPath, "utf8");
const spec = YAML.parse(specText);

function pointer(doc, ref) {
  if (!ref.startsWith("#/")) throw new Error(`unsupported $ref ${ref}`);
  let node = doc;
  for (const raw of ref.slice(2).split("/")) {
    const key = raw.replaceAll("~1", "/").replaceAll("~0", "~");
    node = node?.[key];
    if (node === undefined) throw new Error(`dangling $ref ${ref}`);
  }
  return node;
}

function resolve(node) {
  while (node && typeof node === "object" && typeof node.$ref === "string") node = pointer(spec, node.$ref);
  return node;
}

const ajv = new Ajv2020({ strict: true, strictTypes: false, strictTuples: false, allErrors: true });
addFormats(ajv);
ajv.addFormat("binary", true);
ajv.addVocabulary(["example", "discriminator"]);  // OpenAPI annotations, no assertions

// Component schemas live under $defs of one schema document; refs into them are rewritten.
const rewriteRefs = (schema) =>
  JSON.parse(JSON.stringify(schema).replaceAll('"#/components/schemas/', '"components.json#/$defs/'));
ajv.addSchema({ $id: "components.json", $defs: rewriteRefs(spec.components.schemas) });

const compiled = new Map();
function validator(schema) {
  const key = JSON.stringify(schema);
  if (!compiled.has(key)) compiled.set(key, ajv.compile(rewriteRefs(schema)));
  return compiled.get(key);
}

function validate(schema, value, what) {
  const check = validator(schema);
  const ok = check(value);
  expect(ok, `${what}: ${ajv.errorsText(check.errors, { separator: "; " })}` +
             (ok ? "" : `\n       value: ${JSON.stringify(value).slice(0, 400)}`));
  return ok;
}

const schemaRef = (name) => ({ $ref: `#/components/schemas/${name}` });
const schemaAccepts = (name, value) => validator(schemaRef(name))(value);

// The operation of a concrete path: its template, path item and the operation for `method`.
const templates = Object.keys(spec.paths).map((template) => ({
  template,
  regex: new RegExp("^" + template.replace(/[.]/g, "\\.").replace(/\{[^}]+\}/g, "[^/]+") + "$"),
}));

function operationFor(method, target) {
  const urlPath = target.split("?")[0];
  const match = templates.find((t) => t.regex.test(urlPath));
  if (!match) return null;
  const item = spec.paths[match.template];
  const verb = method === "HEAD" ? "get" : method.toLowerCase();
  return { template: match.template, item, operation: item[verb] };
}

const httpMethods = ["get", "put", "post", "delete", "options", "head", "patch", "trace"];
const transportHeaders = new Set(["server", "content-type", "content-length", "connection", "date",
                                  "keep-alive", "transfer-encoding"]);

function headerValue(schema, text) {
  const s = resolve(schema);
  if (s?.type === "integer") return /^-?[0-9]+$/.test(text) ? Number(text) : text;
  return text;
}

// Checks one response against the spec; returns the parsed body (JSON) or the raw bytes.
function checkResponse(request, response, expectedStatus) {
  const label = `${request.method} ${request.target}${request.note ? ` (${request.note})` : ""}`;
  const { status, headers, body } = response;
  if (expectedStatus !== undefined) {
    expect(status === expectedStatus, `${label}: status ${status}, expected ${expectedStatus}; body ${body.toString().slice(0, 300)}`);
  }
  const found = operationFor(request.method, request.target);
  if (!expect(found, `${label}: no path of the spec matches`)) return null;
  let definition;
  if (!found.operation) {
    // A method the path does not list: the 405 of components/responses/MethodNotAllowed.
    definition = resolve(spec.components.responses.MethodNotAllowed);
    expect(status === 405, `${label}: a method the spec does not list answered ${status}, not 405`);
    const listed = httpMethods.filter((m) => found.item[m]).map((m) => m.toUpperCase());
    if (listed.includes("GET")) listed.push("HEAD");
    const allow = (headers.allow ?? "").split(",").map((m) => m.trim()).filter(Boolean);
    expect(JSON.stringify([...allow].sort()) === JSON.stringify([...listed].sort()),
           `${label}: Allow '${headers.allow}' differs from the spec's methods ${listed.join(", ")}`);
  } else {
    definition = resolve(found.operation.responses[String(status)]);
    if (!expect(definition, `${label}: status ${status} is not documented for ${found.operation.operationId}`)) return null;
  }
  const key = `${request.method === "HEAD" ? "HEAD" : request.method} ${found.template} ${status}`;
  covered.set(key, (covered.get(key) ?? 0) + 1);

  // Headers: every required one present, every present one valid, none undocumented.
  const documented = new Map();
  for (const [name, header] of Object.entries(definition.headers ?? {})) documented.set(name.toLowerCase(), resolve(header));
  for (const [name, header] of documented) {
    const value = headers[name];
    if (value === undefined) {
      expect(!header.required, `${label}: required header ${name} missing`);
      continue;
    }
    validate(header.schema, headerValue(header.schema, value), `${label}: header ${name}: '${value}'`);
  }
  for (const name of Object.keys(headers)) {
    if (transportHeaders.has(name)) continue;
    expect(documented.has(name), `${label}: header ${name} is not documented for status ${status}`);
  }

  // Body.
  const contentType = headers["content-type"];
  if (!definition.content) {
    expect(contentType === undefined, `${label}: Content-Type '${contentType}' on a response without content`);
    expect(body.length === 0, `${label}: ${body.length} body bytes on a response without content`);
    return null;
  }
  if (!expect(contentType, `${label}: no Content-Type`)) return null;
  const essence = contentType.split(";")[0].trim().toLowerCase();
  const media = definition.content[essence];
  if (!expect(media, `${label}: Content-Type ${contentType} is not one of ${Object.keys(definition.content).join(", ")}`)) return null;
  if (request.method === "HEAD") {
    expect(body.length === 0, `${label}: HEAD answered with a body`);
    return null;
  }
  if (essence.endsWith("json")) {
    let parsed;
    try {
      parsed = JSON.parse(body.toString("utf8"));
    } catch (error) {
      expect(false, `${label}: body is not JSON: ${error.message}`);
      return null;
    }
    validate(media.schema, parsed, `${label}: body`);
    return parsed;
  }
  if (essence.startsWith("text/") || essence === "application/yaml") {
    const text = body.toString("utf8");
    validate(media.schema, text, `${label}: body`);
    return text;
  }
  return body;  // binary: the caller checks its layout
}

// ------------------------------------------------------------------------------------------
// HTTP

function send(server, method, target, { headers = {}, body, note, timeoutMs = 40000 } = {}) {
  return new Promise((resolvePromise, reject) => {
    const payload = body === undefined ? undefined : Buffer.isBuffer(body) ? body : Buffer.from(typeof body === "string" ? body : JSON.stringify(body));
    const allHeaders = { ...headers };
    if (payload !== undefined) allHeaders["Content-Length"] = String(payload.length);
    const started = Date.now();
    const request = http.request({ host: "127.0.0.1", port: server.port, method, path: target, headers: allHeaders, agent: false },
      (response) => {
        const chunks = [];
        response.on("data", (chunk) => chunks.push(chunk));
        response.on("end", () => resolvePromise({ status: response.statusCode, headers: response.headers, body: Buffer.concat(chunks), ms: Date.now() - started }));
        response.on("error", reject);
      });
    request.setTimeout(timeoutMs, () => request.destroy(new Error(`no answer within ${timeoutMs} ms`)));
    request.on("error", reject);
    if (payload !== undefined) request.write(payload);
    request.end();
  });
}

// Sends and checks against the spec; returns { response, body } with body parsed when JSON.
async function call(server, method, target, expectedStatus, options = {}) {
  const response = await send(server, method, target, options);
  const body = checkResponse({ method, target, note: options.note ?? server.name }, response, expectedStatus);
  return { response, body };
}

// A raw request (for malformed HTTP): returns the status line's code, headers and body.
function rawRequest(server, text) {
  return new Promise((resolvePromise, reject) => {
    const socket = net.connect(server.port, "127.0.0.1");
    const chunks = [];
    socket.setTimeout(10000, () => socket.destroy(new Error("raw request timed out")));
    socket.on("connect", () => socket.write(text));
    socket.on("data", (chunk) => chunks.push(chunk));
    socket.on("error", reject);
    socket.on("close", () => {
      const data = Buffer.concat(chunks).toString("latin1");
      const split = data.indexOf("\r\n\r\n");
      const head = data.slice(0, split).split("\r\n");
      const status = Number(head[0].split(" ")[1]);
      const headers = {};
      for (const line of head.slice(1)) {
        const colon = line.indexOf(":");
        headers[line.slice(0, colon).trim().toLowerCase()] = line.slice(colon + 1).trim();
      }
      resolvePromise({ status, headers, body: Buffer.from(data.slice(split + 4), "latin1") });
    });
  });
}

// ------------------------------------------------------------------------------------------
// Servers

const servers = [];

async function startServer(name, extraArgs = []) {
  const server = await startBrisance(binary, name, extraArgs, { prefix: "brisance-contract" });
  servers.push(server);
  console.log(`started ${name}: brisance ${server.args.join(" ")} -> port ${server.port}`);
  return server;
}

async function stopServer(server) {
  const result = await stopBrisance(server, 30000);
  if (!expect(result, `${server.name}: did not exit within 30 s of SIGTERM`)) return;
  console.log(`stopped ${server.name} (at ${((Date.now() - startedAt) / 1000).toFixed(1)} s)`);
  expect(result.code === 0 && result.signal === null,
         `${server.name}: exit code ${result.code} (signal ${result.signal}) after SIGTERM, expected 0`);
}

// ------------------------------------------------------------------------------------------
// Scenes and jobs

const threeBlocks = JSON.parse(fs.readFileSync(path.join(root, "scenes", "three_blocks.json"), "utf8"));
const clone = (value) => JSON.parse(JSON.stringify(value));
const json = { "Content-Type": "application/json" };

// Runs for minutes: twenty bodies falling forever (no ground, no sleep) at a tiny fixed step.
const longScene = {
  charges: [{ position: [0, 0.25, 0], mass: 10 }],
  environment: { ground: null },
  generators: [{ type: "blocks", name: "g", counts: [4, 1, 5], size: [0.3, 0.3, 0.3], spacing: [0.2, 0, 0.2], mass: 10, position: [0, 0, 6] }],
  simulation: { duration: 600, time_step: 0.00001, sleep: false },
};

async function submit(server, scene, expectedStatus = 202, headers = {}, extra = {}) {
  const { response, body } = await call(server, "POST", "/v1/jobs", expectedStatus,
                                        { headers: { ...json, ...headers }, body: { scene, ...extra } });
  return { response, job: body };
}

const isFinal = (status) => ["succeeded", "failed", "cancelled"].includes(status);

async function waitFor(server, id, predicate, what, seconds = 60) {
  const deadline = Date.now() + seconds * 1000;
  let job;
  while (Date.now() < deadline) {
    ({ body: job } = await call(server, "GET", `/v1/jobs/${id}?wait=2`, 200));
    if (job && predicate(job)) return job;
  }
  expect(false, `job ${id} did not become ${what} within ${seconds} s (last: ${job?.status})`);
  return job;
}

const unknownId = "j000000000000000000000000";

// ------------------------------------------------------------------------------------------
// The binary frame layout, read from the spec

function readLayout(buffer, layout) {
  const littleEndian = layout.byte_order === "little-endian";
  let offset = 0;
  const sizes = { uint32: 4, float32: 4, float64: 8 };
  const readScalar = (type) => {
    if (offset + sizes[type] > buffer.length) throw new Error(`truncated at byte ${offset} reading ${type}`);
    const value = type === "uint32" ? (littleEndian ? buffer.readUInt32LE(offset) : buffer.readUInt32BE(offset))
                : type === "float32" ? (littleEndian ? buffer.readFloatLE(offset) : buffer.readFloatBE(offset))
                : (littleEndian ? buffer.readDoubleLE(offset) : buffer.readDoubleBE(offset));
    offset += sizes[type];
    return value;
  };
  const lookup = (scopes, name) => {
    for (let i = scopes.length - 1; i >= 0; --i) if (name in scopes[i]) return scopes[i][name];
    throw new Error(`layout repeat '${name}' names no earlier field`);
  };
  const readField = (field, scopes) => {
    if (field.type === "ascii") {
      const text = buffer.toString("latin1", offset, offset + field.length);
      offset += field.length;
      if (field.value !== undefined && text !== field.value) throw new Error(`${field.name} is '${text}', expected '${field.value}'`);
      return text;
    }
    if (field.fields) return readRecord(field.fields, scopes);
    if (field.count) return Array.from({ length: field.count }, () => readScalar(field.type));
    return readScalar(field.type);
  };
  const readRecord = (fields, scopes) => {
    const record = {};
    const inner = [...scopes, record];
    for (const field of fields) {
      if (field.repeat) {
        const n = lookup(inner, field.repeat);
        record[field.name] = Array.from({ length: n }, () => readField(field, inner));
      } else {
        record[field.name] = readField(field, inner);
      }
    }
    return record;
  };
  const value = readRecord(layout.fields, []);
  if (offset !== buffer.length) throw new Error(`${buffer.length - offset} bytes left after the layout`);
  return value;
}

function checkFramesMatch(binary, frames, label) {
  expect(binary.from === frames.from, `${label}: binary from ${binary.from} != JSON ${frames.from}`);
  expect(binary.frame_count === frames.frames.length, `${label}: binary frame count ${binary.frame_count} != JSON ${frames.frames.length}`);
  expect(JSON.stringify(binary.bodies) === JSON.stringify(frames.bodies), `${label}: binary bodies ${binary.bodies} != JSON ${frames.bodies}`);
  let same = true;
  binary.frames.forEach((frame, f) => {
    const other = frames.frames[f];
    if (!other || frame.time !== other.time) same = false;
    frame.poses.forEach((pose, b) => {
      const p = other?.poses[b];
      if (!p) { same = false; return; }
      pose.position.forEach((x, c) => { if (x !== Math.fround(p.position[c])) same = false; });
      pose.orientation.forEach((x, c) => { if (x !== Math.fround(p.orientation[c])) same = false; });
    });
  });
  expect(same, `${label}: binary frames differ from the JSON frames`);
}

function checkGlb(buffer, bodyCount, label) {
  if (!expect(buffer.length >= 20, `${label}: ${buffer.length} bytes is too short for a GLB`)) return;
  expect(buffer.toString("latin1", 0, 4) === "glTF", `${label}: GLB magic is not 'glTF'`);
  expect(buffer.readUInt32LE(4) === 2, `${label}: GLB version ${buffer.readUInt32LE(4)}, expected 2`);
  expect(buffer.readUInt32LE(8) === buffer.length, `${label}: GLB length field ${buffer.readUInt32LE(8)} != ${buffer.length} bytes`);
  const jsonLength = buffer.readUInt32LE(12);
  expect(buffer.readUInt32LE(16) === 0x4e4f534a, `${label}: first GLB chunk is not JSON`);
  try {
    const gltf = JSON.parse(buffer.toString("utf8", 20, 20 + jsonLength));
    expect(gltf.asset?.version === "2.0", `${label}: asset.version ${gltf.asset?.version}`);
    expect(gltf.meshes?.length === bodyCount, `${label}: ${gltf.meshes?.length} meshes for ${bodyCount} bodies`);
  } catch (error) {
    expect(false, `${label}: GLB JSON chunk: ${error.message}`);
  }
}

// ------------------------------------------------------------------------------------------
// The tests

async function probesAndService(s) {
  section("probes, metrics, contract, blast calculator");
  await call(s, "GET", "/healthz", 200);
  const { body: ready } = await call(s, "GET", "/readyz", 200);
  expect(ready?.status === "ready" && ready.workers === 1, `/readyz: ${JSON.stringify(ready)}`);
  await call(s, "HEAD", "/healthz", 200);

  const { response: specResponse, body: served } = await call(s, "GET", "/openapi.yaml", 200);
  expect(served === specText, "/openapi.yaml differs from api/openapi.yaml: the binary is stale, rebuild it");
  expect(specResponse.headers["content-type"] === "application/yaml", `/openapi.yaml Content-Type ${specResponse.headers["content-type"]}`);

  const { body: explosives, response: exResponse } = await call(s, "GET", "/v1/explosives", 200);
  expect(explosives?.explosives.some((e) => e.name === "TNT" && e.tnt_factor === 1), "/v1/explosives lists TNT with factor 1");
  expect(explosives?.explosives.some((e) => e.name === "Composition C-4" && e.tnt_factor === 1.37 && e.impulse_tnt_factor === 1.19),
         "/v1/explosives gives C-4 its two UFC factors");
  await call(s, "GET", "/v1/explosives", 304, { headers: { "If-None-Match": exResponse.headers.etag } });
  await call(s, "GET", "/v1/explosives", 304, { headers: { "If-None-Match": `"nope", W/${exResponse.headers.etag}` }, note: "weak tag in a list" });
  await call(s, "GET", "/v1/explosives", 304, { headers: { "If-None-Match": "*" }, note: "If-None-Match: *" });
  await call(s, "GET", "/v1/explosives", 200, { headers: { "If-None-Match": '"0123"' }, note: "stale tag" });
  await call(s, "HEAD", "/v1/explosives", 200);

  const { body: blast } = await call(s, "GET", "/v1/blast?charge_kg=100&distance_m=15", 200);
  expect(blast && Math.abs(blast.scaled_distance_m_kg13 - 15 / Math.cbrt(100)) < 1e-9, `/v1/blast Z = ${blast?.scaled_distance_m_kg13}`);
  expect(blast?.in_validity_range === true, "/v1/blast 100 kg at 15 m is in the validity range");
  const { body: c4 } = await call(s, "GET", "/v1/blast?charge_kg=10&distance_m=5&explosive=c4&burst=surface&angle_deg=30", 200);
  expect(c4 && Math.abs(c4.tnt_equivalent_kg - 13.7) < 1e-9, `/v1/blast C4 TNT equivalent ${c4?.tnt_equivalent_kg}`);
  expect(c4 && Math.abs(c4.impulse_tnt_equivalent_kg - 11.9) < 1e-9 && c4.inputs.impulse_tnt_factor === 1.19,
         `/v1/blast C4 impulse equivalent ${c4?.impulse_tnt_equivalent_kg}`);
  expect(blast && blast.negative_phase.underpressure_kpa > 0 && blast.negative_phase.underpressure_kpa < blast.incident_overpressure_kpa &&
         Math.abs(blast.negative_phase.duration_ms - 16 / 9 * blast.negative_phase.impulse_kpa_ms / blast.negative_phase.underpressure_kpa) < 1e-9,
         `/v1/blast negative phase ${JSON.stringify(blast?.negative_phase)}`);
  const { body: custom } = await call(s, "GET", "/v1/blast?charge_kg=10&distance_m=5&tnt_factor=1.37&impulse_tnt_factor=1.19", 200);
  const { body: customOne } = await call(s, "GET", "/v1/blast?charge_kg=10&distance_m=5&tnt_factor=1.37", 200);
  expect(custom && customOne && Math.abs(custom.impulse_tnt_equivalent_kg - 11.9) < 1e-9 &&
         custom.incident_overpressure_kpa === customOne.incident_overpressure_kpa &&
         custom.incident_impulse_kpa_ms < customOne.incident_impulse_kpa_ms,
         `/v1/blast custom impulse factor ${custom?.impulse_tnt_equivalent_kg}: same pressure, less impulse`);
  await call(s, "GET", "/v1/blast?charge_kg=1&distance_m=1000", 200, { note: "outside the fits" });
  for (const [query, parameter] of [["distance_m=5", "charge_kg"], ["charge_kg=-1&distance_m=5", "charge_kg"],
                                    ["charge_kg=1", "distance_m"], ["charge_kg=1&distance_m=abc", "distance_m"],
                                    ["charge_kg=1&distance_m=5&explosive=dynamite", "explosive"],
                                    ["charge_kg=1&distance_m=5&burst=underwater", "burst"],
                                    ["charge_kg=1&distance_m=5&angle_deg=91", "angle_deg"],
                                    ["charge_kg=1&distance_m=5&explosive=c4&impulse_tnt_factor=1.2", "impulse_tnt_factor"],
                                    ["charge_kg=1&distance_m=5&tnt_factor=1&impulse_tnt_factor=0", "impulse_tnt_factor"]]) {
    const { body } = await call(s, "GET", `/v1/blast?${query}`, 400);
    expect(body?.errors?.[0]?.parameter === parameter, `/v1/blast?${query}: errors[0].parameter ${body?.errors?.[0]?.parameter}, expected ${parameter}`);
  }

  // Every bad parameter at once.
  const { body: many } = await call(s, "GET", "/v1/blast?charge_kg=-1&distance_m=x&angle_deg=91", 400, { note: "three bad parameters" });
  expect(many?.errors?.map((e) => e.parameter).join(",") === "charge_kg,distance_m,angle_deg",
         `/v1/blast three bad parameters: ${JSON.stringify(many?.errors)}`);
  expect(blast?.inputs?.explosive === "TNT" && blast?.inputs?.charge_kg === 100, `/v1/blast echoes its inputs: ${JSON.stringify(blast?.inputs)}`);

  // The structural-response calculators (docs/response.md).
  const wall = JSON.parse(fs.readFileSync(path.join(root, "scenes", "elements", "rc_wall.json"), "utf8"));
  const { body: response } = await call(s, "POST", "/v1/response", 200, { headers: json, body: { element: wall, charge: { charge_kg: 100, distance_m: 15 } } });
  expect(response && response.peak_displacement_m > 0 && typeof response.damage === "string", `/v1/response: ${JSON.stringify(response)?.slice(0, 200)}`);
  expect(response?.load?.peak_pressure_kpa === blast?.reflected_overpressure_kpa, "/v1/response loads with the /v1/blast reflected pressure");
  await call(s, "POST", "/v1/response", 200, { headers: json, body: { element: wall, pulse: { peak_kpa: 100, duration_ms: 10, shape: "friedlander" }, history: false }, note: "pulse, no history" });
  await call(s, "POST", "/v1/response", 400, { headers: json, body: "{not json" });
  await call(s, "POST", "/v1/response", 415, { headers: { "Content-Type": "text/plain" }, body: "x" });
  const { body: bad } = await call(s, "POST", "/v1/response", 422, { headers: json, body: { element: { ...wall, mass_kg: -1 }, pulse: { peak_kpa: 0, duration_ms: 1 } } });
  expect(bad?.errors?.map((e) => e.pointer).join(",") === "/element/mass_kg,/pulse/peak_kpa", `/v1/response 422 pointers: ${JSON.stringify(bad?.errors)}`);
  await call(s, "POST", "/v1/response", 422, { headers: json, body: { element: wall, pulse: { peak_kpa: 1, duration_ms: 1e9 } }, note: "unbounded work" });
  const { body: pi } = await call(s, "POST", "/v1/pi", 200, { headers: json, body: { element: wall, ductility: 3, points: 10 } });
  expect(pi?.points?.length === 10 && pi.impulsive_asymptote_kpa_ms > 0, `/v1/pi: ${JSON.stringify(pi)?.slice(0, 200)}`);
  await call(s, "POST", "/v1/pi", 400, { headers: json, body: "[" });
  await call(s, "POST", "/v1/pi", 415, { headers: { "Content-Type": "text/plain" }, body: "x" });
  await call(s, "POST", "/v1/pi", 422, { headers: json, body: { element: wall, points: 1000 } });

  const { body: metrics, response: metricsResponse } = await call(s, "GET", "/metrics", 200);
  expect(metricsResponse.headers["content-type"] === "text/plain; version=0.0.4; charset=utf-8",
         `/metrics Content-Type ${metricsResponse.headers["content-type"]}`);
  expect(typeof metrics === "string" && metrics.includes('brisance_http_requests_total{route="/v1/blast",method="GET",status="400"}'),
         "/metrics counts the /v1/blast 400s");

  const { response: echoed } = await call(s, "GET", "/healthz", 200, { headers: { "X-Request-Id": "contract-test.1_a" }, note: "client request id" });
  expect(echoed.headers["x-request-id"] === "contract-test.1_a", `X-Request-Id not echoed: ${echoed.headers["x-request-id"]}`);
  const { response: replaced } = await call(s, "GET", "/healthz", 200, { headers: { "X-Request-Id": "not a token!" }, note: "insane request id" });
  expect(replaced.headers["x-request-id"] !== "not a token!", "an insane X-Request-Id is replaced");

  // A path outside the contract: a not-found problem (checked by hand, no operation to match).
  const nowhere = await send(s, "GET", "/v1/nothing-here");
  expect(nowhere.status === 404 && nowhere.headers["content-type"] === "application/problem+json",
         `GET /v1/nothing-here: ${nowhere.status} ${nowhere.headers["content-type"]}`);
  validate(schemaRef("NotFoundProblem"), JSON.parse(nowhere.body.toString() || "null"), "GET /v1/nothing-here: body");
}

async function methodNotAllowed(s) {
  section("405 for every path, Allow matching the spec");
  const id = unknownId;
  for (const template of Object.keys(spec.paths)) {
    if (template === "/healthz" || template === "/readyz") continue;  // probes answer any method
    const target = template.replace("{id}", id);
    const item = spec.paths[template];
    for (const method of ["PUT", "PATCH", "POST", "DELETE", "GET"]) {
      if (item[method.toLowerCase()]) continue;
      await call(s, method, target, 405, { headers: method === "POST" || method === "PUT" || method === "PATCH" ? json : {} });
    }
  }
}

async function jobsLifecycle(s) {
  section("submit, watch, results, frames, meshes, glb");
  const { job, response } = await submit(s, threeBlocks);
  if (!job) return null;
  expect(response.headers.location === `/v1/jobs/${job.id}`, `Location ${response.headers.location}`);
  expect(job.status === "queued" || job.status === "running" || job.status === "succeeded", `new job status ${job.status}`);
  const done = await waitFor(s, job.id, (j) => isFinal(j.status), "finished");
  if (!expect(done?.status === "succeeded", `three_blocks job ended ${done?.status}: ${JSON.stringify(done?.error)}`)) return null;
  expect(done.links.result && done.links.frames && done.links.meshes && done.links.glb, "a succeeded job links its results");
  expect(done.stats && done.progress === 1, "a succeeded job has stats and progress 1");

  // Long-poll on a finished job answers at once.
  const { response: polled } = await call(s, "GET", `/v1/jobs/${job.id}?wait=10`, 200, { note: "long-poll, final job" });
  expect(polled.ms < 5000, `?wait=10 on a finished job took ${polled.ms} ms: it should answer at once`);
  const { response: current } = await call(s, "GET", `/v1/jobs/${job.id}`, 200);
  expect(current.headers["retry-after"] === undefined, "no Retry-After on a finished job");
  await call(s, "GET", `/v1/jobs/${job.id}`, 304, { headers: { "If-None-Match": current.headers.etag } });
  await call(s, "GET", `/v1/jobs/${job.id}?wait=2`, 304, { headers: { "If-None-Match": current.headers.etag }, note: "long-poll, final, matching tag" });
  await call(s, "HEAD", `/v1/jobs/${job.id}`, 200);
  await call(s, "GET", `/v1/jobs/${job.id}?wait=31`, 400);
  await call(s, "GET", `/v1/jobs/${job.id}?wait=x`, 400);

  const { body: result, response: resultResponse } = await call(s, "GET", `/v1/jobs/${job.id}/result`, 200);
  expect(resultResponse.headers.etag === current.headers.etag, "the result's ETag is the job's");
  expect(result?.bodies.length === 3 && result.frame_count === result.frame_times.length, "result: 3 bodies, frame_times per frame");
  expect(result?.job?.id === job.id, "result.job is the job");

  const { body: frames } = await call(s, "GET", `/v1/jobs/${job.id}/frames`, 200);
  expect(frames?.from === 0 && frames.to === result.frame_count && frames.frames.length === result.frame_count,
         `frames default to all ${result?.frame_count} frames`);
  expect(JSON.stringify(frames?.bodies) === JSON.stringify(result?.animated), "frames default to the animated bodies");
  const window = `/v1/jobs/${job.id}/frames?from=1&to=4&bodies=2,0`;
  const { body: part } = await call(s, "GET", window, 200, { headers: { Accept: "application/json" } });
  expect(part?.frames.length === 3 && part.frames[0].index === 1 && JSON.stringify(part.bodies) === "[2,0]", "frames ?from=1&to=4&bodies=2,0");
  await call(s, "GET", window, 200, { headers: { Accept: "*/*" }, note: "Accept */*" });
  const layout = spec.paths["/v1/jobs/{id}/frames"].get.responses["200"].content["application/octet-stream"]["x-brisance-binary-layout"];
  for (const [target, json] of [[window, part], [`/v1/jobs/${job.id}/frames`, frames],
                                 [`/v1/jobs/${job.id}/frames?from=5&to=5`, null], [`/v1/jobs/${job.id}/frames?bodies=`, null]]) {
    const { body: bytes } = await call(s, "GET", target, 200, { headers: { Accept: "application/octet-stream" }, note: "binary" });
    if (!bytes) continue;
    try {
      const parsed = readLayout(bytes, layout);
      checks++;
      const reference = json ?? (await call(s, "GET", target, 200, { note: "JSON twin" })).body;
      checkFramesMatch(parsed, reference, `${target} binary`);
    } catch (error) {
      expect(false, `${target} binary: does not follow the spec's layout: ${error.message}`);
    }
  }
  await call(s, "HEAD", `/v1/jobs/${job.id}/frames`, 200, { headers: { Accept: "application/octet-stream" }, note: "binary" });
  await call(s, "GET", `/v1/jobs/${job.id}/frames`, 406, { headers: { Accept: "image/png" } });
  for (const query of ["from=62", "from=3&to=2", "to=99", "bodies=3", "bodies=0,x", "from=-1"]) {
    const { body } = await call(s, "GET", `/v1/jobs/${job.id}/frames?${query}`, 400);
    expect(body?.errors?.length === 1, `frames?${query}: one error in errors[]`);
  }

  const { body: meshes, response: meshResponse } = await call(s, "GET", `/v1/jobs/${job.id}/meshes`, 200);
  expect(meshes?.bodies.length === 3 && meshes.bodies.every((b) => b.mesh.triangles.length === 12), "meshes: 3 boxes of 12 triangles");
  await call(s, "GET", `/v1/jobs/${job.id}/meshes`, 304, { headers: { "If-None-Match": meshResponse.headers.etag } });

  const { body: scene } = await call(s, "GET", `/v1/jobs/${job.id}/scene`, 200);
  expect(scene?.objects?.length === 3, "scene: the three blocks as submitted");

  const { body: glb } = await call(s, "GET", `/v1/jobs/${job.id}/result.glb`, 200);
  if (glb) checkGlb(glb, 3, "result.glb");
  await call(s, "HEAD", `/v1/jobs/${job.id}/result.glb`, 200);

  await call(s, "POST", `/v1/jobs/${job.id}/cancel`, 409, { note: "finished job" });
  for (const tail of ["", "/cancel", "/scene", "/result", "/frames", "/meshes", "/result.glb"]) {
    await call(s, tail === "/cancel" ? "POST" : "GET", `/v1/jobs/${unknownId}${tail}`, 404);
  }
  await call(s, "DELETE", `/v1/jobs/${unknownId}`, 404);
  return job.id;
}

async function submissionErrors(s) {
  section("submission errors and idempotency");
  await call(s, "POST", "/v1/jobs", 400, { headers: json, body: "{not json", note: "malformed JSON" });
  await call(s, "POST", "/v1/jobs", 415, { headers: { "Content-Type": "text/plain" }, body: { scene: threeBlocks } });
  await call(s, "POST", "/v1/jobs", 202, { body: { scene: threeBlocks }, note: "no Content-Type is JSON" })
    .then(({ body }) => body && call(s, "DELETE", `/v1/jobs/${body.id}`, 204));
  const { body: invalid } = await call(s, "POST", "/v1/jobs", 422, { headers: json, body: { scene: { charges: [] }, colour: 1 } });
  const pointers = (invalid?.errors ?? []).map((e) => e.pointer);
  expect(pointers.includes("/colour") && pointers.includes("/scene/charges"), `422 pointers ${pointers.join(", ")}`);
  await call(s, "POST", "/v1/jobs", 422, { headers: json, body: [1, 2], note: "not an object" });
  await call(s, "POST", "/v1/jobs", 400, { headers: { ...json, "Idempotency-Key": "k".repeat(256) }, body: { scene: threeBlocks }, note: "Idempotency-Key too long" });

  const key = `contract-${process.pid}-${Date.now()}`;
  const { job: first } = await submit(s, threeBlocks, 202, { "Idempotency-Key": key });
  const { job: again, response: againResponse } = await submit(s, threeBlocks, 200, { "Idempotency-Key": key });
  expect(first && again && first.id === again.id, "an idempotent retry returns the same job");
  expect(againResponse.headers.location === `/v1/jobs/${first?.id}`, "the retry's Location names the first job");
  const other = clone(threeBlocks);
  other.simulation.duration = 1;
  await submit(s, other, 422, { "Idempotency-Key": key });

  // 413: a body over --body-limit-mb (0.01 MiB here). The server closes the connection after
  // answering, so a client still sending may see a reset instead; try a few times.
  for (const target of ["/v1/jobs", "/v1/response", "/v1/pi"]) {
    let tooLarge = null;
    for (let attempt = 0; attempt < 5 && !tooLarge; ++attempt) {
      try {
        tooLarge = await send(s, "POST", target, { headers: json, body: JSON.stringify({ scene: threeBlocks, pad: "x".repeat(20000) }) });
      } catch (error) {
        console.log(`  (413 attempt ${attempt + 1}: ${error.code ?? error.message})`);
      }
    }
    if (expect(tooLarge, `POST ${target} with a 20 kB body: no answer in 5 attempts`)) {
      checkResponse({ method: "POST", target, note: "body over the limit" }, tooLarge, 413);
    }
  }

  // 400 bad-request from the transport, for every operation: a request that is not HTTP/1.1.
  for (const [template, item] of Object.entries(spec.paths)) {
    for (const verb of httpMethods.filter((m) => item[m])) {
      const target = template.replace("{id}", unknownId);
      const method = verb.toUpperCase();
      const raw = await rawRequest(s, `${method} ${target} HTTP/1.1\r\nHost: x\r\nContent-Length: nope\r\n\r\n`);
      checkResponse({ method, target, note: "malformed HTTP" }, raw, 400);
    }
  }
  if (first) await call(s, "DELETE", `/v1/jobs/${first.id}`, 204);
}

// The Element schema and the server's element parser (sim/response/element.cpp) agree: the
// examples and a full element pass both, each broken element fails both.
async function elementSchemaAgreement(s) {
  section("the Element schema agrees with the server's validation");
  const full = { mass_kg: 500, loaded_area_m2: 2, damping_ratio: 0.02, factors: { load: 0.64, mass: 0.5 }, support: { span_m: 3 },
                 limits: "rc_flexure",
                 resistance: { type: "membrane", stiffness_n_per_m: 2e6, yield_resistance_n: 1e5, membrane_onset_m: 0.1, membrane_stiffness_n_per_m: 1e5 } };
  const valid = [["every field", full]];
  for (const file of fs.readdirSync(path.join(root, "scenes", "elements")).filter((f) => f.endsWith(".json")).sort()) {
    valid.push([`scenes/elements/${file}`, JSON.parse(fs.readFileSync(path.join(root, "scenes", "elements", file), "utf8"))]);
  }
  for (const [name, element] of valid) {
    expect(schemaAccepts("Element", element), `Element schema rejects '${name}': ${ajv.errorsText(validator(schemaRef("Element")).errors)}`);
    await call(s, "POST", "/v1/pi", 200, { headers: json, body: { element, points: 4 }, note: name });
  }
  const broken = [
    ["unknown field", { ...full, colour: "red" }],
    ["no mass", (({ mass_kg, ...rest }) => rest)(full)],
    ["zero area", { ...full, loaded_area_m2: 0 }],
    ["damping 1", { ...full, damping_ratio: 1 }],
    ["unknown resistance", { ...full, resistance: { type: "plastic", stiffness_n_per_m: 1 } }],
    ["unknown limits", { ...full, limits: "glass" }],
    ["span 0", { ...full, support: { span_m: 0 } }],
    ["factor -1", { ...full, factors: { load: -1 } }],
  ];
  for (const [name, element] of broken) {
    expect(!schemaAccepts("Element", element), `Element schema accepts the broken element '${name}'`);
    const { body } = await call(s, "POST", "/v1/pi", 422, { headers: json, body: { element, ductility: 2 }, note: name });
    expect(body?.errors?.every((e) => e.pointer.startsWith("/element")), `'${name}': pointers ${JSON.stringify(body?.errors)}`);
  }
}

async function sceneSchemaAgreement(s) {
  section("the Scene schema agrees with the server's validation");
  const base = () => clone(threeBlocks);
  const tetra = { type: "mesh", vertices: [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], triangles: [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]] };
  const everything = {
    charges: [{ position: [0, 0, -4], mass: 5, explosive: { tnt_factor: 1.2 }, burst: "surface", burst_model: "factor_1_8" },
              { position: [0, 1, -5], mass: 2, explosive: "composition-b", burst: "air", burst_model: "hemispherical" }],
    environment: { gravity: [0, -9.81, 0], air_density: 1.2, ambient_pressure: 101000, ground: { height: 0, friction: 0.4, restitution: 0.1 } },
    objects: [
      { name: "crate", shape: { type: "box", size: [1, 1, 1] }, position: [0, 0.5, 0], orientation: [0, 0, 0, 1], material: "Wood",
        friction: 0.3, drag_coefficient: 1.1, anchored: false, blocks: true, rotates: true },
      { name: "tetra", shape: tetra, position: [3, 0, 0], density: 500, rotates: false },
      { name: "post", shape: { type: "box", size: [0.2, 2, 0.2] }, position: [-3, 1, 0], mass: 40, anchored: true, blocks: false },
    ],
    generators: [
      { type: "brick_wall", name: "wall", position: [0, 0, 4], orientation: [0, 0, 0, 1], rows: 2, columns: 2, brick_size: [0.4, 0.15, 0.1],
        brick_mass: 3, friction: 0.6, mortar_gap: 0.01 },
      { type: "blocks", name: "stack", position: [5, 0, 5], orientation: [0, 0.7071068, 0, 0.7071068], counts: [1, 2, 1], size: [0.3, 0.3, 0.3],
        spacing: [0, 0.01, 0], density: 800, friction: 0.5 },
    ],
    simulation: { duration: 0.05, frame_rate: 20, tolerance: 0.01, seed: 7, clearing: false, occlusion: "off", integrator: "rk4",
                  pulse: "triangle_same_period", max_panel_area: 0.5, linear_damping: 0.1, angular_damping: 0.1, rotation_factor: 0.5, sleep: false, collisions: "on" },
  };
  const valid = [
    ["every field", everything],
    ["fixed step, no ground, seed 2^53", { ...base(), environment: { ground: null }, simulation: { duration: 0.05, time_step: 0.001, seed: 9007199254740991 } }],
    ["generators only", { charges: [{ position: [0, 0.5, -3], mass: 1, explosive: "TNT" }],
                          generators: [{ type: "blocks", name: "b", counts: [1, 1, 1], size: [1, 1, 1], mass: 5 }], simulation: { duration: 0.05 } }],
  ];
  for (const file of fs.readdirSync(path.join(root, "scenes")).filter((f) => f.endsWith(".json")).sort()) {
    valid.push([`scenes/${file}`, JSON.parse(fs.readFileSync(path.join(root, "scenes", file), "utf8"))]);
  }
  for (const [name, scene] of valid) {
    const accepts = schemaAccepts("Scene", scene);
    expect(accepts, `Scene schema rejects the valid scene '${name}': ${ajv.errorsText(validator(schemaRef("Scene")).errors)}`);
    expect(schemaAccepts("JobRequest", { scene, priority: -100 }), `JobRequest schema rejects '${name}' with priority -100`);
    const { job } = await submit(s, scene, 202, {}, { priority: -100 });
    if (job) await call(s, "DELETE", `/v1/jobs/${job.id}`, 204);
  }

  const edit = (f) => { const scene = base(); f(scene); return scene; };
  const invalid = [
    ["unknown top-level field", edit((x) => { x.colour = 1; }), "/scene/colour"],
    ["no charge", edit((x) => { x.charges = []; }), "/scene/charges"],
    ["negative mass", edit((x) => { x.charges[0].mass = -1; }), "/scene/charges/0/mass"],
    ["unknown charge field", edit((x) => { x.charges[0].yield = 1; }), "/scene/charges/0/yield"],
    ["tnt_factor 0", edit((x) => { x.charges[0].explosive = { tnt_factor: 0 }; }), "/scene/charges/0/explosive/tnt_factor"],
    ["burst 'ground'", edit((x) => { x.charges[0].burst = "ground"; }), "/scene/charges/0/burst"],
    ["burst_model 'x1.8'", edit((x) => { x.charges[0].burst_model = "x1.8"; }), "/scene/charges/0/burst_model"],
    ["unknown ground field", edit((x) => { x.environment = { ground: { bounciness: 1 } }; }), "/scene/environment/ground/bounciness"],
    ["restitution 2", edit((x) => { x.environment = { ground: { restitution: 2 } }; }), "/scene/environment/ground/restitution"],
    ["negative air density", edit((x) => { x.environment = { air_density: -1 }; }), "/scene/environment/air_density"],
    ["gravity of 2", edit((x) => { x.environment = { gravity: [0, -9.81] }; }), "/scene/environment/gravity"],
    ["mass and density", edit((x) => { x.objects[0].mass = 1; x.objects[0].density = 1; }), "/scene/objects/0/density"],
    ["no mass, density or material", edit((x) => { delete x.objects[0].material; }), "/scene/objects/0/mass"],
    ["box size 0", edit((x) => { x.objects[0].shape.size[1] = 0; }), "/scene/objects/0/shape/size/1"],
    ["sphere", edit((x) => { x.objects[0].shape = { type: "sphere", radius: 1 }; }), "/scene/objects/0/shape/type"],
    ["box with vertices", edit((x) => { x.objects[0].shape.vertices = []; }), "/scene/objects/0/shape/vertices"],
    ["material cheese", edit((x) => { x.objects[0].material = "cheese"; }), "/scene/objects/0/material"],
    ["fracture", edit((x) => { x.objects[0].fracture = {}; }), "/scene/objects/0/fracture"],
    ["breakage 'wobbly'", edit((x) => { x.objects[0] = { name: "pane", shape: { type: "box", size: [1, 1, 0.006] }, position: [0, 1, 0], material: "glass", fracture: { breakage: "wobbly" } }; }), "/scene/objects/0/fracture/breakage"],
    ["orientation of 3", edit((x) => { x.objects[0].orientation = [0, 0, 1]; }), "/scene/objects/0/orientation"],
    ["empty name", edit((x) => { x.objects[0].name = ""; }), "/scene/objects/0/name"],
    ["drag_coefficient 0", edit((x) => { x.objects[0].drag_coefficient = 0; }), "/scene/objects/0/drag_coefficient"],
    ["anchored 'yes'", edit((x) => { x.objects[0].anchored = "yes"; }), "/scene/objects/0/anchored"],
    ["file shape without path", edit((x) => { x.objects[0].shape = { type: "file", node: "Crate" }; }), "/scene/objects/0/shape/path"],
    ["asset shape with a size", edit((x) => { x.objects[0].shape = { type: "asset", asset: "a", size: [1, 1, 1] }; }), "/scene/objects/0/shape/size"],
    ["mesh of 3 triangles", edit((x) => { x.objects[0].shape = { ...tetra, triangles: tetra.triangles.slice(0, 3) }; }), "/scene/objects/0/shape/triangles"],
    ["mesh index -1", edit((x) => { x.objects[0].shape = { ...tetra, triangles: [[0, 2, -1], ...tetra.triangles.slice(1)] }; }), "/scene/objects/0/shape/triangles/0/2"],
    ["no objects", edit((x) => { delete x.objects; }), "/scene/objects"],
    ["window without size", edit((x) => { x.generators = [{ type: "window", name: "w" }]; }), "/scene/generators/0/size"],
    ["brick wall without rows", edit((x) => { x.generators = [{ type: "brick_wall", name: "w", columns: 2, brick_size: [0.4, 0.1, 0.1], brick_mass: 1 }]; }), "/scene/generators/0/rows"],
    ["brick wall rows 0", edit((x) => { x.generators = [{ type: "brick_wall", name: "w", rows: 0, columns: 2, brick_size: [0.4, 0.1, 0.1], brick_mass: 1 }]; }), "/scene/generators/0/rows"],
    ["blocks with mass and density", edit((x) => { x.generators = [{ type: "blocks", name: "b", counts: [1, 1, 1], size: [1, 1, 1], mass: 1, density: 1, position: [0, 0, 9] }]; }), "/scene/generators/0/density"],
    ["blocks without mass", edit((x) => { x.generators = [{ type: "blocks", name: "b", counts: [1, 1, 1], size: [1, 1, 1], position: [0, 0, 9] }]; }), "/scene/generators/0/mass"],
    ["blocks unknown field", edit((x) => { x.generators = [{ type: "blocks", name: "b", counts: [1, 1, 1], size: [1, 1, 1], mass: 1, rows: 2, position: [0, 0, 9] }]; }), "/scene/generators/0/rows"],
    ["time_step and tolerance", edit((x) => { x.simulation.time_step = 0.001; x.simulation.tolerance = 0.01; }), "/scene/simulation/tolerance"],
    ["occlusion 'maybe'", edit((x) => { x.simulation.occlusion = "maybe"; }), "/scene/simulation/occlusion"],
    ["duration 601", edit((x) => { x.simulation.duration = 601; }), "/scene/simulation/duration"],
    ["tolerance 1", edit((x) => { x.simulation.tolerance = 1; }), "/scene/simulation/tolerance"],
    ["time_step 0.2", edit((x) => { x.simulation.time_step = 0.2; }), "/scene/simulation/time_step"],
    ["seed -1", edit((x) => { x.simulation.seed = -1; }), "/scene/simulation/seed"],
    ["seed 1.5", edit((x) => { x.simulation.seed = 1.5; }), "/scene/simulation/seed"],
    ["integrator 'verlet'", edit((x) => { x.simulation.integrator = "verlet"; }), "/scene/simulation/integrator"],
    ["unknown simulation field", edit((x) => { x.simulation.fps = 30; }), "/scene/simulation/fps"],
  ];
  for (const [name, scene, expectedPointer] of invalid) {
    expect(!schemaAccepts("Scene", scene), `Scene schema accepts the invalid scene '${name}'`);
    const { body } = await call(s, "POST", "/v1/jobs", 422, { headers: json, body: { scene }, note: name });
    const pointers = (body?.errors ?? []).map((e) => e.pointer);
    expect(pointers.includes(expectedPointer), `'${name}': the server's errors point at ${pointers.join(", ")}, expected ${expectedPointer}`);
  }
  for (const [name, request, expectedPointer] of [["priority 101", { scene: base(), priority: 101 }, "/priority"],
                                                  ["priority 1.5", { scene: base(), priority: 1.5 }, "/priority"],
                                                  ["unknown job field", { scene: base(), colour: 1 }, "/colour"],
                                                  ["no scene", { priority: 1 }, "/scene"]]) {
    expect(!schemaAccepts("JobRequest", request), `JobRequest schema accepts the invalid job '${name}'`);
    const { body } = await call(s, "POST", "/v1/jobs", 422, { headers: json, body: request, note: name });
    const pointers = (body?.errors ?? []).map((e) => e.pointer);
    expect(pointers.includes(expectedPointer), `'${name}': the server's errors point at ${pointers.join(", ")}, expected ${expectedPointer}`);
  }
}

async function assets(s, small) {
  section("assets: upload, get, refusals, asset and file shapes");
  const assetsDir = path.join(root, "tests", "assets");
  const glb = fs.readFileSync(path.join(assetsDir, "crate.glb"));
  const { body: created } = await call(s, "POST", "/v1/assets", 201, { headers: { "Content-Type": "model/gltf-binary" }, body: glb });
  expect(JSON.stringify(created?.nodes) === JSON.stringify(["Crate", "Pallet"]), `crate.glb nodes: ${JSON.stringify(created?.nodes)}`);
  await call(s, "POST", "/v1/assets", 200, { headers: { "Content-Type": "model/gltf-binary" }, body: glb, note: "same file again" });
  const id = created?.id ?? "0".repeat(64);
  await call(s, "GET", `/v1/assets/${id}`, 200);
  await call(s, "HEAD", `/v1/assets/${id}`, 200);
  await call(s, "GET", `/v1/assets/${"0".repeat(64)}`, 404);
  await call(s, "POST", "/v1/assets?format=obj", 201, { body: fs.readFileSync(path.join(assetsDir, "crate.obj")), note: "OBJ by ?format" });
  await call(s, "POST", "/v1/assets", 422, { headers: { "Content-Type": "model/obj" }, body: fs.readFileSync(path.join(assetsDir, "open_crate.obj")), note: "open mesh" });
  await call(s, "POST", "/v1/assets", 422, { headers: { "Content-Type": "model/gltf+json" }, body: "{}", note: "not glTF" });
  await call(s, "POST", "/v1/assets", 415, { headers: { "Content-Type": "text/plain" }, body: "v 0 0 0" });
  await call(s, "POST", "/v1/assets?format=fbx", 400, { body: "x" });
  await call(s, "POST", "/v1/assets", 413, { headers: { "Content-Type": "model/obj" }, body: Buffer.alloc(20000, 0x20), note: "over the body limit" });
  await call(small, "POST", "/v1/assets", 413, { headers: { "Content-Type": "model/gltf-binary" }, body: glb, note: "over --max-asset-mb" });

  const crate = (shape) => ({ ...clone(threeBlocks), objects: [{ name: "crate", shape, position: [0, 0.5, 6], density: 500 }] });
  const assetScene = crate({ type: "asset", asset: id, node: "Crate" });
  expect(schemaAccepts("Scene", assetScene), "Scene schema rejects an asset shape");
  const { job } = await submit(s, assetScene, 202);
  if (job) {
    const done = await waitFor(s, job.id, (j) => j.status === "succeeded" || j.status === "failed", "finished");
    expect(done?.status === "succeeded", `the asset job ended ${done?.status}`);
    await call(s, "DELETE", `/v1/jobs/${job.id}`, 204);
  }
  const fileScene = crate({ type: "file", path: "crate.glb" });
  expect(schemaAccepts("Scene", fileScene), "Scene schema rejects a file shape");
  const { body: refused } = await call(s, "POST", "/v1/jobs", 422, { headers: json, body: { scene: fileScene }, note: "file shape over HTTP" });
  const pointers = (refused?.errors ?? []).map((e) => e.pointer);
  expect(pointers.includes("/scene/objects/0/shape/type"), `file shape over HTTP: errors at ${pointers.join(", ")}`);
}

async function listing(s) {
  section("listing, pagination, Link");
  const ids = [];
  for (let i = 0; i < 3; ++i) {
    const { job } = await submit(s, threeBlocks);
    if (job) ids.push(job.id);
  }
  for (const id of ids) await waitFor(s, id, (j) => isFinal(j.status), "finished");
  const { body: page1, response: r1 } = await call(s, "GET", "/v1/jobs?limit=2", 200);
  expect(page1?.jobs.length === 2 && page1.next_cursor !== null, "limit=2 with more jobs: 2 jobs and a next_cursor");
  expect(page1?.jobs[0]?.id === ids[2], "jobs are listed newest first");
  const link = r1.headers.link ?? "";
  const next = /^<([^>]+)>; rel="next"$/.exec(link)?.[1];
  expect(next === `/v1/jobs?limit=2&cursor=${page1?.next_cursor}`, `Link '${link}' names the next page`);
  if (next) {
    const { body: page2 } = await call(s, "GET", next, 200);
    expect(page2?.jobs[0]?.id === ids[0], "the next page continues after the first");
  }
  const { body: done, response: rd } = await call(s, "GET", "/v1/jobs?status=succeeded&limit=1", 200);
  expect(done?.jobs.every((j) => j.status === "succeeded"), "status=succeeded lists only succeeded jobs");
  expect((rd.headers.link ?? "").includes("&status=succeeded"), "the Link keeps the status filter");
  const { response: all } = await call(s, "GET", "/v1/jobs", 200);
  await call(s, "GET", "/v1/jobs", 304, { headers: { "If-None-Match": all.headers.etag } });
  await call(s, "HEAD", "/v1/jobs", 200);
  for (const query of ["status=done", "limit=0", "limit=501", "cursor=-1", "limit=ten"]) {
    await call(s, "GET", `/v1/jobs?${query}`, 400);
  }
  const { body: queue, response: rq } = await call(s, "GET", "/v1/queue", 200);
  expect(queue?.workers.total === 1 && queue.oldest_queued === null, `queue: ${JSON.stringify(queue)}`);
  await call(s, "GET", "/v1/queue", 304, { headers: { "If-None-Match": rq.headers.etag } });
  for (const id of ids) await call(s, "DELETE", `/v1/jobs/${id}`, 204);
  await call(s, "GET", `/v1/jobs/${ids[0]}`, 404, { note: "deleted" });
  await call(s, "DELETE", `/v1/jobs/${ids[0]}`, 404, { note: "deleted twice" });
}

async function queueAndCancel(s) {
  section("queue full (429), cancel (200/202/409), long-poll, results not ready (409)");
  const { job: running } = await submit(s, longScene);
  if (!running) return;
  await waitFor(s, running.id, (j) => j.status === "running", "running", 30);
  await new Promise((r) => setTimeout(r, 300));  // the queued-count cache lives 100 ms
  const key = `queued-${process.pid}`;
  const { job: queued } = await submit(s, threeBlocks, 202, { "Idempotency-Key": key });
  const { response: full } = await submit(s, threeBlocks, 429);
  expect(full.headers["retry-after"] === "5", `429 Retry-After ${full.headers["retry-after"]}`);
  const { job: replay } = await submit(s, threeBlocks, 200, { "Idempotency-Key": key });
  expect(replay?.id === queued?.id, "an idempotent retry still finds its job when the queue is full");
  const other = clone(threeBlocks);
  other.simulation.frame_rate = 10;
  await submit(s, other, 422, { "Idempotency-Key": key });
  const { body: queue } = await call(s, "GET", "/v1/queue", 200);
  expect(queue?.counts.queued === 1 && queue.counts.running === 1 && queue.workers.busy === 1 && queue.oldest_queued !== null,
         `queue with one running and one queued: ${JSON.stringify(queue)}`);
  const { body: ready } = await call(s, "GET", "/readyz", 200);
  expect(ready?.status === "ready", "ready while busy");
  if (!queued) return;

  // Results of a queued and of a running job: 409 with Retry-After.
  for (const tail of ["/result", "/frames", "/meshes", "/result.glb"]) {
    const { response } = await call(s, "GET", `/v1/jobs/${queued.id}${tail}`, 409, { note: "queued" });
    expect(response.headers["retry-after"] === "1", `409 on a queued job's ${tail} has Retry-After: 1`);
  }
  await call(s, "GET", `/v1/jobs/${running.id}/result`, 409, { note: "running" });
  const { response: busy } = await call(s, "GET", `/v1/jobs/${queued.id}`, 200);
  expect(busy.headers["retry-after"] === "1", "a queued job has Retry-After");

  // Long-poll a job that does not change: 304 with If-None-Match, 200 without, after the wait.
  const { response: held } = await call(s, "GET", `/v1/jobs/${queued.id}?wait=2`, 304, { headers: { "If-None-Match": busy.headers.etag }, note: "long-poll, unchanged" });
  expect(held.ms >= 1800 && held.ms < 15000, `?wait=2 on an unchanged job answered after ${held.ms} ms`);
  const { response: held2 } = await call(s, "GET", `/v1/jobs/${queued.id}?wait=1`, 200, { note: "long-poll, no tag" });
  expect(held2.ms >= 800 && held2.ms < 15000, `?wait=1 without a tag answered after ${held2.ms} ms`);

  // A long-poll is woken by the change: cancel the queued job while it waits.
  const poll = call(s, "GET", `/v1/jobs/${queued.id}?wait=20`, 200, { headers: { "If-None-Match": busy.headers.etag }, note: "long-poll woken" });
  await new Promise((r) => setTimeout(r, 300));
  const { body: cancelled, response: cancelResponse } = await call(s, "POST", `/v1/jobs/${queued.id}/cancel`, 200, { note: "queued" });
  expect(cancelled?.status === "cancelled", `cancelling a queued job: status ${cancelled?.status}`);
  expect(cancelResponse.headers.location === `/v1/jobs/${queued.id}`, "cancel's Location");
  const { body: woken, response: wokenResponse } = await poll;
  expect(woken?.status === "cancelled" && wokenResponse.ms < 10000, `the long-poll woke with ${woken?.status} after ${wokenResponse.ms} ms`);
  await call(s, "GET", `/v1/jobs/${queued.id}/result`, 409, { note: "cancelled" })
    .then(({ response }) => expect(response.headers["retry-after"] === undefined, "no Retry-After on a cancelled job's 409"));
  await call(s, "POST", `/v1/jobs/${queued.id}/cancel`, 409, { note: "cancelled" });

  const { body: stopping } = await call(s, "POST", `/v1/jobs/${running.id}/cancel`, 202, { note: "running" });
  expect(stopping?.cancel_requested === true, "cancelling a running job sets cancel_requested");
  const end = await waitFor(s, running.id, (j) => isFinal(j.status), "cancelled", 30);
  expect(end?.status === "cancelled", `the running job ended ${end?.status}`);
  expect(end && end.error === null && end.stats === null, "a cancelled job has no error and no stats");
  await call(s, "DELETE", `/v1/jobs/${running.id}`, 204);

  // Deleting a running job stops it.
  const { job: second } = await submit(s, longScene);
  if (second) {
    await waitFor(s, second.id, (j) => j.status === "running", "running", 30);
    await call(s, "DELETE", `/v1/jobs/${second.id}`, 204, { note: "running" });
    await call(s, "GET", `/v1/jobs/${second.id}`, 404, { note: "deleted while running" });
  }
}

async function authentication(s, keys) {
  section("API keys: 401 without a key, 403 for a read key on POST and DELETE");
  const read = { Authorization: `Bearer ${keys.read}` };
  const write = { Authorization: `Bearer ${keys.write}` };
  const { job } = await submit(s, threeBlocks, 202, write);
  const id = job?.id ?? unknownId;
  for (const [template, item] of Object.entries(spec.paths)) {
    const target = template.replace("{id}", id) + (template === "/v1/blast" ? "?charge_kg=1&distance_m=5" : "");
    for (const verb of httpMethods.filter((m) => item[m])) {
      const method = verb.toUpperCase();
      const operation = item[verb];
      const open = Array.isArray(operation.security) && operation.security.length === 0;
      const body = method === "POST" && template === "/v1/jobs" ? { scene: threeBlocks } : undefined;
      const headers = body ? json : {};
      if (open) {
        await call(s, method, target, 200, { note: "no key, open probe" });
        continue;
      }
      const { response: none } = await call(s, method, target, 401, { headers, body, note: "no key" });
      expect(none.headers["www-authenticate"] === 'Bearer realm="brisance"', `401 WWW-Authenticate ${none.headers["www-authenticate"]}`);
      await call(s, method, target, 401, { headers: { ...headers, Authorization: "Bearer bk_0000000000000000000000000000000000000000" }, body, note: "unknown key" });
      await call(s, method, target, 401, { headers: { ...headers, Authorization: `Basic ${keys.read}` }, body, note: "not Bearer" });
      const scopes = (operation.security ?? spec.security).flatMap((requirement) => requirement.apiKey ?? []);
      if (scopes.includes("write")) {
        await call(s, method, target, 403, { headers: { ...headers, ...read }, body, note: "read key" });
      } else {
        const response = await send(s, method, target, { headers: { ...headers, ...read }, body });
        expect(response.status !== 401 && response.status !== 403, `${method} ${target} with a read key: ${response.status}`);
      }
    }
  }
  // Keys are checked before the method: a read key on a method /metrics lacks is a 403, not a 405.
  const early = await send(s, "POST", "/metrics", { headers: read });
  expect(early.status === 403, `POST /metrics with a read key: ${early.status}, expected 403 (keys before methods)`);
  validate(schemaRef("ForbiddenProblem"), JSON.parse(early.body.toString() || "null"), "POST /metrics with a read key: body");
  await call(s, "GET", "/v1/queue", 200, { headers: write, note: "a write key can read" });
  if (job) {
    await waitFor2(s, job.id, write);
    await call(s, "DELETE", `/v1/jobs/${job.id}`, 204, { headers: write });
  }
}

async function waitFor2(s, id, headers) {
  const deadline = Date.now() + 60000;
  while (Date.now() < deadline) {
    const { body } = await call(s, "GET", `/v1/jobs/${id}?wait=2`, 200, { headers });
    if (body && isFinal(body.status)) return body;
  }
  return null;
}

function makeKey(scope) {
  const out = execFileSync(binary, ["api-key", "--name", `contract-${scope}`, "--scope", scope], { encoding: "utf8" });
  const key = /^key:\s*(\S+)/m.exec(out)?.[1];
  const line = /^line:\s*(.+)$/m.exec(out)?.[1];
  if (!key || !line) throw new Error(`brisance api-key printed no key and line:\n${out}`);
  return { key, line };
}

// ------------------------------------------------------------------------------------------

const coverageReport = () => {
  const documented = [];
  for (const [template, item] of Object.entries(spec.paths)) {
    for (const verb of httpMethods.filter((m) => item[m])) {
      for (const status of Object.keys(item[verb].responses)) documented.push(`${verb.toUpperCase()} ${template} ${status}`);
    }
  }
  const hit = documented.filter((key) => covered.has(key));
  const missed = documented.filter((key) => !covered.has(key));
  const operations = new Set([...covered.keys()].map((key) => key.split(" ").slice(0, 2).join(" ")));
  const statuses = new Set([...covered.keys()].map((key) => key.split(" ")[2]));
  console.log(`\ncoverage: ${operations.size} operations (incl. HEAD and 405 probes), ` +
              `${hit.length} of ${documented.length} documented (operation, status) pairs, statuses seen: ${[...statuses].sort().join(" ")}`);
  console.log(`not provoked (need a failing store, a crash or a transport fault): ${missed.join("; ")}`);
};

const timeout = setTimeout(() => {
  console.error("contract.api: still running after 240 s; giving up");
  for (const s of servers) s.child.kill("SIGKILL");
  process.exit(1);
}, 240000);

let crashed = null;
try {
  const main = await startServer("main", ["--body-limit-mb", "0.01"]);
  const queue = await startServer("queue", ["--max-queue", "1", "--max-asset-mb", "0.001"]);
  const keyFile = path.join(fs.mkdtempSync(path.join(os.tmpdir(), "brisance-contract-keys-")), "keys");
  const readKey = makeKey("read");
  const writeKey = makeKey("write");
  fs.writeFileSync(keyFile, `# contract test keys\n${readKey.line}\n${writeKey.line}\n`);
  const auth = await startServer("auth", ["--api-keys", keyFile]);

  for (const [name, run] of [["probes", () => probesAndService(main)], ["405", () => methodNotAllowed(main)],
                             ["lifecycle", () => jobsLifecycle(main)], ["submission", () => submissionErrors(main)],
                             ["scene schema", () => sceneSchemaAgreement(main)], ["assets", () => assets(main, queue)],
                             ["element schema", () => elementSchemaAgreement(main)], ["listing", () => listing(main)],
                             ["queue", () => queueAndCancel(queue)],
                             ["auth", () => authentication(auth, { read: readKey.key, write: writeKey.key })]]) {
    try {
      await run();
    } catch (error) {
      expect(false, `${name}: ${error.stack ?? error}`);
    }
  }
  section("shutdown: SIGTERM, exit 0");
  for (const s of [main, queue, auth]) await stopServer(s);
  fs.rmSync(path.dirname(keyFile), { recursive: true, force: true });
} catch (error) {
  crashed = error;
} finally {
  for (const s of servers) {
    if (!s.stopped) s.child.kill("SIGKILL");
  }
  clearTimeout(timeout);
}

if (crashed) {
  console.error(`contract.api: ${crashed.stack ?? crashed}`);
  failures.push(String(crashed.message ?? crashed));
}
coverageReport();
if (failures.length) {
  for (const s of servers) {
    console.log(`\n-- last log lines of ${s.name}:\n${s.log.slice(-20).join("\n")}`);
  }
  console.log(`\ncontract.api: ${failures.length} of ${checks} checks failed:`);
  for (const f of failures) console.log(`  - ${f.split("\n")[0]}`);
  console.log(`${checks - failures.length} passed, ${failures.length} failed`);
  process.exit(1);
}
console.log(`\ncontract.api: all ${checks} checks passed against ${specPath}`);
console.log(`${checks} passed, 0 failed`);
process.exit(0);
