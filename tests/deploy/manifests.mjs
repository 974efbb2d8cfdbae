// tests/deploy/manifests.mjs: checks deploy/kubernetes and deploy/compose.yaml without a cluster
// or a container runtime (CTest: deploy.manifests).
//   1. Each Kubernetes object against the Kubernetes API schemas (kubernetes-models: types,
//      required fields, formats such as quantities), and once more through TypeScript, whose
//      excess-property check finds unknown fields (a misspelt `livenesProbe` passes the schemas).
//   2. deploy/compose.yaml against the Compose specification and dclint's rules.
//   3. What the files must agree on, with each other and with the binary: every BRISANCE_*
//      variable is one the service reads, grace periods cover the drain, probes hit /healthz and
//      /readyz on the served port, names and selectors refer to what exists, the pods run as the
//      image's user.
//   4. That the checks can fail: a list of broken copies of the files, each of which must be
//      reported.
// Usage: node manifests.mjs [REPOSITORY_ROOT]. Exit 0: all good; 1: problems (listed); 2: the
// npm packages are missing (run `npm ci --prefix tests/deploy`).
import { spawnSync } from "node:child_process";
import fs from "node:fs";
import os from "node:os";
import path from "node:path";
import { createRequire } from "node:module";
import { fileURLToPath } from "node:url";

const here = path.dirname(fileURLToPath(import.meta.url));
const root = path.resolve(process.argv[2] ?? path.join(here, "..", ".."));
const require = createRequire(import.meta.url);

let YAML;
let ts;
try {
  YAML = require("yaml");
  ts = require("typescript");
  require.resolve("kubernetes-models/apps/v1/Deployment");
  require.resolve("dclint/package.json");
} catch {
  console.error("deploy.manifests: npm packages missing: run `npm ci --prefix tests/deploy`");
  process.exit(2);
}

// Variables the deploy files may set before the binary reads them (none now: the PostgreSQL store
// and the blob folder of issue 14 are read). Once the sources read one, drop it from here.
const PENDING_VARIABLES = new Set([]);
// `brisance serve` finishes the requests in flight for up to this long before the grace period
// of running jobs starts (cli/serve_command.cpp: server.stop(10 s)).
const REQUEST_DRAIN_S = 10;

// ---------------------------------------------------------------------------------------------
// Reading the files

function readKubernetes(dir) {
  const objects = [];
  let kustomization = null;
  for (const name of fs.readdirSync(dir).sort()) {
    if (!/\.ya?ml$/.test(name)) continue;
    const file = path.join(dir, name);
    const docs = YAML.parseAllDocuments(fs.readFileSync(file, "utf8"));
    docs.forEach((doc, index) => {
      if (doc.errors.length) throw new Error(`${file}: ${doc.errors[0].message}`);
      const value = doc.toJS();
      if (value === null) return;
      if (name === "kustomization.yaml") kustomization = value;
      else objects.push({ file: name, index, object: value });
    });
  }
  return { objects, kustomization };
}

// The Dockerfile's runtime user and its ENV defaults (tests/deploy/deploy_test.py checks
// the rest of that file).
function readDockerfile(file) {
  const text = fs.readFileSync(file, "utf8").replace(/\\\n/g, " ");
  const stages = text.split(/^FROM /m);
  const runtime = stages[stages.length - 1];
  const user = /^USER\s+(\d+)(?::(\d+))?/m.exec(runtime);
  const env = {};
  for (const match of runtime.matchAll(/^ENV\s+(.+)$/gm)) {
    for (const pair of match[1].matchAll(/(\w+)=(\S+)/g)) env[pair[1]] = pair[2];
  }
  return { uid: user ? Number(user[1]) : null, gid: user?.[2] ? Number(user[2]) : null, env };
}

// Every BRISANCE_* name that the binary's sources mention: what the service reads.
function variablesRead() {
  const names = new Set();
  const walk = (dir) => {
    for (const entry of fs.readdirSync(dir, { withFileTypes: true })) {
      const full = path.join(dir, entry.name);
      if (entry.isDirectory()) walk(full);
      else if (/\.(cpp|hpp)$/.test(entry.name)) {
        for (const m of fs.readFileSync(full, "utf8").matchAll(/"(BRISANCE_[A-Z0-9_]+)"/g)) names.add(m[1]);
      }
    }
  };
  walk(path.join(root, "cli"));
  walk(path.join(root, "server"));
  return names;
}

function readInputs() {
  return {
    kubernetes: readKubernetes(path.join(root, "deploy", "kubernetes")),
    kubernetesFiles: fs.readdirSync(path.join(root, "deploy", "kubernetes")).filter((n) => /\.ya?ml$/.test(n)).sort(),
    compose: YAML.parse(fs.readFileSync(path.join(root, "deploy", "compose.yaml"), "utf8"), { merge: true }),
    composeText: fs.readFileSync(path.join(root, "deploy", "compose.yaml"), "utf8"),
    dockerfile: readDockerfile(path.join(root, "deploy", "container", "Dockerfile")),
    variables: variablesRead(),
  };
}

// ---------------------------------------------------------------------------------------------
// 1. Kubernetes schemas

function modelPath(apiVersion, kind) {
  const [group, version] = apiVersion.includes("/") ? apiVersion.split("/") : [null, apiVersion];
  return group ? `kubernetes-models/${group}/${version}/${kind}` : `kubernetes-models/${version}/${kind}`;
}

async function checkKubernetesSchemas(objects, problems) {
  for (const { file, object } of objects) {
    const where = `${file}: ${object.kind} ${object.metadata?.name ?? "?"}`;
    let model;
    try {
      model = (await import(modelPath(object.apiVersion, object.kind)))[object.kind];
    } catch {
      problems.push(`${where}: unknown apiVersion/kind ${object.apiVersion} ${object.kind}`);
      continue;
    }
    try {
      new model(object).validate();
    } catch (error) {
      problems.push(`${where}: ${error.message}`);
    }
  }
}

// Unknown fields: each object becomes a typed constant of its kubernetes-models interface, and
// TypeScript's excess-property check names any field the API does not have.
function checkKubernetesFields(objects, problems) {
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), "brisance-deploy-ts-"));
  try {
    fs.symlinkSync(path.join(here, "node_modules"), path.join(dir, "node_modules"), "dir");
    const lines = [];
    const spans = [];
    objects.forEach(({ file, object }, i) => {
      lines.push(`import type { I${object.kind} as T${i} } from "${modelPath(object.apiVersion, object.kind)}";`);
    });
    objects.forEach(({ file, object }, i) => {
      const first = lines.length;
      lines.push(`export const m${i}: T${i} = ${JSON.stringify(object, null, 2)};`);
      spans.push({ first, last: lines.length + JSON.stringify(object, null, 2).split("\n").length, file, object });
    });
    const source = path.join(dir, "manifests.ts");
    fs.writeFileSync(source, lines.join("\n"));
    const program = ts.createProgram([source], {
      noEmit: true,
      strict: true,
      skipLibCheck: true,
      module: ts.ModuleKind.CommonJS,
      moduleResolution: ts.ModuleResolutionKind.Node10,
      target: ts.ScriptTarget.ES2022,
      types: [],
    });
    for (const d of ts.getPreEmitDiagnostics(program)) {
      const message = ts.flattenDiagnosticMessageText(d.messageText, " ");
      if (d.file && d.file.fileName === source && d.start !== undefined) {
        const { line } = d.file.getLineAndCharacterOfPosition(d.start);
        const span = spans.find((s) => line >= s.first && line < s.last);
        const text = d.file.text.split("\n")[line].trim();
        problems.push(`${span ? `${span.file}: ${span.object.kind} ${span.object.metadata?.name}` : "manifests"}: ${message} (at ${text})`);
      } else {
        problems.push(`TypeScript: ${message}`);
      }
    }
  } finally {
    fs.rmSync(dir, { recursive: true, force: true });
  }
}

// ---------------------------------------------------------------------------------------------
// 2. Compose

function checkComposeSchema(text, problems) {
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), "brisance-deploy-compose-"));
  try {
    const file = path.join(dir, "compose.yaml");
    fs.writeFileSync(file, text);
    // The ordering rules are style only; everything else, warnings included, must pass.
    const run = spawnSync(process.execPath, [
      path.join(path.dirname(require.resolve("dclint/package.json")), "bin", "dclint.cjs"), file, "--no-color", "--max-warnings", "0",
      "--disable-rule", "service-keys-order", "services-alphabetical-order", "top-level-properties-order",
    ], { encoding: "utf8" });
    if (run.status !== 0) {
      problems.push(`compose.yaml: dclint (exit ${run.status}):\n${(run.stdout + run.stderr).trim()}`);
    }
  } finally {
    fs.rmSync(dir, { recursive: true, force: true });
  }
}

// ---------------------------------------------------------------------------------------------
// 3. What the files must agree on

function seconds(duration) {
  const m = /^(?:(\d+)m)?(?:(\d+)s)?$/.exec(String(duration));
  if (!m || (!m[1] && !m[2])) return NaN;
  return Number(m[1] ?? 0) * 60 + Number(m[2] ?? 0);
}

function checkVariables(where, names, variables, problems) {
  for (const name of names) {
    if (!name.startsWith("BRISANCE_")) continue;
    if (!variables.has(name) && !PENDING_VARIABLES.has(name)) {
      problems.push(`${where}: ${name} is not a variable brisance serve reads (docs/service.md)`);
    }
  }
}

function labelsMatch(selector, labels) {
  return Object.entries(selector ?? {}).every(([k, v]) => labels?.[k] === v) && Object.keys(selector ?? {}).length > 0;
}

function checkKubernetesAgreement(inputs, problems) {
  const { objects, kustomization } = inputs.kubernetes;
  const find = (kind, name) => objects.find((o) => o.object.kind === kind && (!name || o.object.metadata?.name === name))?.object;
  for (const kind of ["Deployment", "Service", "ConfigMap", "Secret", "PodDisruptionBudget", "HorizontalPodAutoscaler"]) {
    if (!find(kind)) problems.push(`kubernetes: no ${kind}`);
  }
  if (!kustomization) {
    problems.push("kubernetes: no kustomization.yaml");
  } else {
    const listed = [...(kustomization.resources ?? [])].sort();
    const present = inputs.kubernetesFiles.filter((n) => n !== "kustomization.yaml");
    if (JSON.stringify(listed) !== JSON.stringify(present)) {
      problems.push(`kustomization.yaml: resources ${JSON.stringify(listed)} are not the files ${JSON.stringify(present)}`);
    }
  }
  const deployment = find("Deployment");
  if (!deployment) return;
  const pod = deployment.spec?.template?.spec ?? {};
  const podLabels = deployment.spec?.template?.metadata?.labels;
  const container = pod.containers?.find((c) => c.name === "brisance") ?? pod.containers?.[0];
  if (!container) {
    problems.push("deployment.yaml: no container");
    return;
  }
  if (!labelsMatch(deployment.spec?.selector?.matchLabels, podLabels)) problems.push("deployment.yaml: selector does not match the pod labels");

  // Settings: the ConfigMap the container reads, and the variables set one by one.
  const configMaps = (container.envFrom ?? []).filter((e) => e.configMapRef).map((e) => e.configMapRef.name);
  const settings = {};
  for (const name of configMaps) {
    const map = find("ConfigMap", name);
    if (!map) problems.push(`deployment.yaml: envFrom ConfigMap ${name} does not exist`);
    else Object.assign(settings, map.data);
  }
  checkVariables("configmap.yaml", Object.keys(settings), inputs.variables, problems);
  checkVariables("deployment.yaml", (container.env ?? []).map((e) => e.name), inputs.variables, problems);
  const secretKeys = (name) => {
    const secret = find("Secret", name);
    return secret ? Object.keys({ ...secret.data, ...secret.stringData }) : null;
  };
  for (const e of container.env ?? []) {
    const ref = e.valueFrom?.secretKeyRef;
    if (ref && !(secretKeys(ref.name) ?? []).includes(ref.key)) problems.push(`deployment.yaml: ${e.name} refers to a missing secret key ${ref.name}/${ref.key}`);
  }
  if (!(container.env ?? []).some((e) => e.name === "BRISANCE_STORE" && e.valueFrom?.secretKeyRef)) {
    problems.push("deployment.yaml: BRISANCE_STORE (the PostgreSQL URL) must come from a Secret");
  }

  // Port and probes.
  const port = Number(settings.BRISANCE_PORT ?? inputs.dockerfile.env.BRISANCE_PORT ?? 8080);
  const http = (container.ports ?? []).find((p) => p.name === "http");
  if (!http || http.containerPort !== port) problems.push(`deployment.yaml: container port 'http' must be BRISANCE_PORT ${port}`);
  if ((settings.BRISANCE_BIND ?? inputs.dockerfile.env.BRISANCE_BIND) !== "0.0.0.0") problems.push("configmap.yaml: BRISANCE_BIND must be 0.0.0.0 for probes and the Service to reach the pod");
  const probe = (name, pathWanted) => {
    const p = container[name]?.httpGet;
    if (!p || p.path !== pathWanted || (p.port !== "http" && p.port !== port)) problems.push(`deployment.yaml: ${name} must GET ${pathWanted} on the http port`);
  };
  probe("livenessProbe", "/healthz");
  probe("readinessProbe", "/readyz");

  // Resources: requests and limits, and no more workers than the CPU limit gives cores.
  for (const kind of ["requests", "limits"]) {
    for (const resource of ["cpu", "memory"]) {
      if (container.resources?.[kind]?.[resource] === undefined) problems.push(`deployment.yaml: no resources.${kind}.${resource}`);
    }
  }
  const cpuLimit = String(container.resources?.limits?.cpu ?? "");
  const cores = cpuLimit.endsWith("m") ? Number(cpuLimit.slice(0, -1)) / 1000 : Number(cpuLimit);
  const workers = Number(settings.BRISANCE_WORKERS);
  if (!(workers >= 1) || workers > Math.max(1, Math.floor(cores))) problems.push(`configmap.yaml: BRISANCE_WORKERS (${settings.BRISANCE_WORKERS}) must be set, at most the CPU limit (${cpuLimit})`);

  // Security: the image's user, no root, no privilege escalation, read-only root file system.
  const podSecurity = pod.securityContext ?? {};
  const containerSecurity = container.securityContext ?? {};
  if (podSecurity.runAsNonRoot !== true) problems.push("deployment.yaml: securityContext.runAsNonRoot must be true");
  if (podSecurity.runAsUser !== inputs.dockerfile.uid) problems.push(`deployment.yaml: runAsUser ${podSecurity.runAsUser} is not the image's USER ${inputs.dockerfile.uid}`);
  if (containerSecurity.allowPrivilegeEscalation !== false) problems.push("deployment.yaml: allowPrivilegeEscalation must be false");
  if (containerSecurity.readOnlyRootFilesystem !== true) problems.push("deployment.yaml: readOnlyRootFilesystem must be true");
  if (!(containerSecurity.capabilities?.drop ?? []).includes("ALL")) problems.push("deployment.yaml: capabilities must drop ALL");

  // Writable mounts: the data folder (with a read-only root, it must be a volume).
  const mounts = container.volumeMounts ?? [];
  const volumes = pod.volumes ?? [];
  const data = settings.BRISANCE_DATA ?? inputs.dockerfile.env.BRISANCE_DATA;
  if (!mounts.some((m) => m.mountPath === data && !m.readOnly)) problems.push(`deployment.yaml: the data folder ${data} must be a writable volume`);
  for (const m of mounts) {
    if (!volumes.some((v) => v.name === m.name)) problems.push(`deployment.yaml: volumeMount ${m.name} has no volume`);
  }
  for (const v of volumes) {
    if (v.secret && !secretKeys(v.secret.secretName)) problems.push(`deployment.yaml: volume ${v.name} uses a missing Secret ${v.secret.secretName}`);
  }
  // The keys file is a key of the mounted keys Secret.
  const keysFile = settings.BRISANCE_API_KEYS;
  if (keysFile) {
    const mount = mounts.find((m) => keysFile.startsWith(m.mountPath + "/"));
    const volume = mount && volumes.find((v) => v.name === mount.name);
    const key = mount && keysFile.slice(mount.mountPath.length + 1);
    if (!volume?.secret || !(secretKeys(volume.secret.secretName) ?? []).includes(key)) problems.push(`deployment.yaml: BRISANCE_API_KEYS ${keysFile} is not a key of a mounted Secret`);
  }

  // Stopping: preStop, then the request drain and BRISANCE_GRACE_S must fit the pod's grace.
  const grace = Number(settings.BRISANCE_GRACE_S ?? 10);
  const preStop = container.lifecycle?.preStop?.exec?.command;
  const preStopS = preStop && preStop[0] === "sleep" ? Number(preStop[1]) : 0;
  const needed = preStopS + REQUEST_DRAIN_S + grace;
  if (!((pod.terminationGracePeriodSeconds ?? 30) > needed)) problems.push(`deployment.yaml: terminationGracePeriodSeconds ${pod.terminationGracePeriodSeconds ?? 30} must exceed preStop ${preStopS} + ${REQUEST_DRAIN_S} + BRISANCE_GRACE_S ${grace}`);

  // The Service, the budget and the autoscaler point at these pods.
  const service = find("Service");
  if (service) {
    if (!labelsMatch(service.spec?.selector, podLabels)) problems.push("service.yaml: selector does not match the pod labels");
    for (const p of service.spec?.ports ?? []) {
      if (p.targetPort !== "http" && p.targetPort !== port) problems.push(`service.yaml: targetPort ${p.targetPort} is not the container's http port`);
    }
  }
  const pdb = find("PodDisruptionBudget");
  if (pdb && !labelsMatch(pdb.spec?.selector?.matchLabels, podLabels)) problems.push("poddisruptionbudget.yaml: selector does not match the pod labels");
  const hpa = find("HorizontalPodAutoscaler");
  if (hpa) {
    const target = hpa.spec?.scaleTargetRef ?? {};
    if (target.kind !== "Deployment" || target.name !== deployment.metadata?.name) problems.push("horizontalpodautoscaler.yaml: scaleTargetRef is not the Deployment");
    if ((hpa.spec?.minReplicas ?? 1) < 2) problems.push("horizontalpodautoscaler.yaml: minReplicas below 2 leaves the PodDisruptionBudget nothing to keep");
  }
}

function checkComposeAgreement(inputs, problems) {
  const services = inputs.compose?.services ?? {};
  const nodes = Object.entries(services).filter(([, s]) => s.build?.dockerfile === "deploy/container/Dockerfile" || String(s.image ?? "").startsWith("brisance"));
  const databases = Object.entries(services).filter(([, s]) => String(s.image ?? "").startsWith("postgres:"));
  if (nodes.length < 2) problems.push("compose.yaml: fewer than 2 brisance nodes");
  if (databases.length !== 1) problems.push("compose.yaml: needs one postgres service");
  for (const [name, service] of Object.entries(services)) {
    if (!service.healthcheck?.test) problems.push(`compose.yaml: service ${name} has no healthcheck`);
  }
  const dbName = databases[0]?.[0];
  const blobVolumes = new Map();
  for (const [name, service] of nodes) {
    const env = service.environment ?? {};
    if (Array.isArray(env)) {
      problems.push(`compose.yaml: ${name}: write environment as a map`);
      continue;
    }
    checkVariables(`compose.yaml ${name}`, Object.keys(env), inputs.variables, problems);
    let store;
    try {
      store = new URL(String(env.BRISANCE_STORE ?? "").replace(/\$\{[^}]*\}/g, "x"));
    } catch {
      store = null;
    }
    if (!store || store.protocol !== "postgres:" || store.hostname !== dbName) problems.push(`compose.yaml: ${name}: BRISANCE_STORE must be a postgres:// URL on the ${dbName} service`);
    if (service.depends_on?.[dbName]?.condition !== "service_healthy") problems.push(`compose.yaml: ${name} must wait for ${dbName} to be healthy`);
    const blobs = env.BRISANCE_BLOBS;
    const mount = (service.volumes ?? []).map((v) => String(v).split(":")).find(([, target]) => target === blobs);
    if (!blobs || !mount) problems.push(`compose.yaml: ${name}: BRISANCE_BLOBS must be a mounted volume`);
    else blobVolumes.set(name, mount[0]);
    const grace = Number(env.BRISANCE_GRACE_S ?? 10);
    const stop = seconds(service.stop_grace_period ?? "10s");
    if (!(stop > REQUEST_DRAIN_S + grace)) problems.push(`compose.yaml: ${name}: stop_grace_period ${service.stop_grace_period ?? "10s"} must exceed ${REQUEST_DRAIN_S} + BRISANCE_GRACE_S ${grace}`);
    const test = service.healthcheck?.test ?? [];
    if (!test.some((t) => String(t).includes("brisance-healthcheck"))) problems.push(`compose.yaml: ${name}: healthcheck must use the image's brisance-healthcheck`);
  }
  const shared = new Set(blobVolumes.values());
  if (blobVolumes.size >= 2 && shared.size !== 1) problems.push("compose.yaml: the nodes must share one blob volume");
  for (const volume of shared) {
    if (!(volume in (inputs.compose.volumes ?? {}))) problems.push(`compose.yaml: volume ${volume} is not declared`);
  }
}

function checkDockerfileUser(inputs, problems) {
  if (!(inputs.dockerfile.uid > 0)) problems.push("Dockerfile: the runtime stage must end with a numeric non-root USER");
  checkVariables("Dockerfile", Object.keys(inputs.dockerfile.env), inputs.variables, problems);
}

async function checkAll(inputs, { schemas = true, fields = true, compose = true } = {}) {
  const problems = [];
  if (schemas) await checkKubernetesSchemas(inputs.kubernetes.objects, problems);
  if (fields) checkKubernetesFields(inputs.kubernetes.objects, problems);
  if (compose) checkComposeSchema(inputs.composeText, problems);
  checkKubernetesAgreement(inputs, problems);
  checkComposeAgreement(inputs, problems);
  checkDockerfileUser(inputs, problems);
  return problems;
}

// ---------------------------------------------------------------------------------------------
// 4. Broken copies that must be caught

const deploymentOf = (inputs) => inputs.kubernetes.objects.find((o) => o.object.kind === "Deployment").object;
const containerOf = (inputs) => deploymentOf(inputs).spec.template.spec.containers[0];
const configOf = (inputs) => inputs.kubernetes.objects.find((o) => o.object.kind === "ConfigMap").object.data;
const nodeOf = (inputs) => Object.values(inputs.compose.services).find((s) => s.build);

const BROKEN = [
  ["a misspelt Kubernetes field", /does not exist in type/, { fields: true }, (i) => { containerOf(i).livenesProbe = containerOf(i).livenessProbe; delete containerOf(i).livenessProbe; }],
  ["a quantity that is not one", /format "quantity"/, { schemas: true }, (i) => { containerOf(i).resources.limits.memory = "2 gigs"; }],
  ["a string for an integer", /replicas must be integer/, { schemas: true }, (i) => { deploymentOf(i).spec.replicas = "2"; }],
  ["a readiness probe on /healthz", /readinessProbe must GET \/readyz/, {}, (i) => { containerOf(i).readinessProbe.httpGet.path = "/healthz"; }],
  ["a pod grace shorter than the drain", /terminationGracePeriodSeconds 30/, {}, (i) => { deploymentOf(i).spec.template.spec.terminationGracePeriodSeconds = 30; }],
  ["a variable the service does not read", /BRISANCE_WORKER is not a variable/, {}, (i) => { configOf(i).BRISANCE_WORKER = "2"; }],
  ["more workers than the CPU limit", /BRISANCE_WORKERS \(8\)/, {}, (i) => { configOf(i).BRISANCE_WORKERS = "8"; }],
  ["a root pod", /runAsUser 0/, {}, (i) => { deploymentOf(i).spec.template.spec.securityContext.runAsUser = 0; }],
  ["a Service selecting other pods", /service.yaml: selector/, {}, (i) => { i.kubernetes.objects.find((o) => o.object.kind === "Service").object.spec.selector = { app: "other" }; }],
  ["a kustomization missing a file", /kustomization.yaml: resources/, {}, (i) => { i.kubernetes.kustomization.resources.pop(); }],
  ["a misspelt Compose key", /must NOT have additional properties/, { compose: true }, (i) => { i.composeText = i.composeText.replace("stop_grace_period:", "stop_grace_periode:"); }],
  ["a Compose stop period shorter than the drain", /stop_grace_period 20s/, {}, (i) => { nodeOf(i).stop_grace_period = "20s"; }],
  ["a Compose node on another database", /BRISANCE_STORE must be a postgres/, {}, (i) => { nodeOf(i).environment.BRISANCE_STORE = "postgres://u:p@elsewhere:5432/db"; }],
];

async function main() {
  const problems = await checkAll(readInputs());
  let failed = problems.length > 0;
  if (failed) {
    console.log(`deploy files: ${problems.length} problem(s):\n  ${problems.join("\n  ")}`);
  } else {
    console.log("deploy files: Kubernetes schemas and fields, Compose spec, agreement: ok");
  }
  let caught = 0;
  for (const [name, expected, only, breakIt] of BROKEN) {
    const inputs = readInputs();
    breakIt(inputs);
    const found = await checkAll(inputs, { schemas: !!only.schemas, fields: !!only.fields, compose: !!only.compose });
    const hit = found.find((p) => expected.test(p));
    if (!hit) {
      console.log(`not caught: ${name} (expected ${expected}; got ${JSON.stringify(found)})`);
      failed = true;
    } else {
      caught += 1;
      console.log(`caught ${name}: ${hit.replace(/\s+/g, " ").slice(0, 200)}`);
    }
  }
  const pendingRead = [...PENDING_VARIABLES].filter((v) => readInputs().variables.has(v));
  if (pendingRead.length) console.log(`note: the service now reads ${pendingRead.join(", ")}: remove them from PENDING_VARIABLES`);
  const passed = (problems.length === 0 ? 1 : 0) + caught;
  console.log(`${passed} passed, ${BROKEN.length + 1 - passed} failed`);
  process.exit(failed ? 1 : 0);
}

await main();
