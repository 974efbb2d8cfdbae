// Validates .glb files with the official Khronos glTF validator (npm package gltf-validator).
//
//   node validate.mjs FILE_OR_DIR...
//
// A directory stands for the .glb files directly inside it. Prints every error and warning and
// a count of infos and hints per file, then a summary line. Exits 1 if any file has an error or
// cannot be read, 2 on bad usage, a missing validator or no file to validate. Warnings, infos and
// hints do not fail the run. Run by CTest as io.gltf_validator (tests/io.cmake).
import { readFile, readdir, stat } from 'node:fs/promises';
import path from 'node:path';

const SEVERITY = ['error', 'warning', 'info', 'hint'];

let validator;
try {
  validator = (await import('gltf-validator')).default;
} catch (error) {
  console.error(`validate.mjs: cannot load gltf-validator (${error.message}).\n` +
                'Install it with: npm ci --prefix tests/gltf');
  process.exit(2);
}

async function glbFiles(args) {
  const files = [];
  for (const arg of args) {
    if ((await stat(arg)).isDirectory()) {
      const names = (await readdir(arg)).filter((name) => name.endsWith('.glb')).sort();
      files.push(...names.map((name) => path.join(arg, name)));
    } else {
      files.push(arg);
    }
  }
  return files;
}

async function validate(file) {
  const bytes = new Uint8Array(await readFile(file));
  const report = await validator.validateBytes(bytes, {
    uri: path.basename(file),
    format: 'glb',
    maxIssues: 0,  // unlimited: never hide an error behind a cap
    writeTimestamp: false,
  });
  const issues = report.issues;
  const info = report.info ?? {};
  console.log(`${file}: ${issues.numErrors} errors, ${issues.numWarnings} warnings, ` +
              `${issues.numInfos} infos, ${issues.numHints} hints ` +
              `(${info.drawCallCount ?? 0} draw calls, ${info.totalTriangleCount ?? 0} triangles, ` +
              `${info.totalVertexCount ?? 0} vertices, ${info.animationCount ?? 0} animations)`);
  const minorCounts = new Map();
  for (const message of issues.messages) {
    const severity = SEVERITY[message.severity] ?? `severity ${message.severity}`;
    if (message.severity <= 1) {
      const where = message.pointer ?? (message.offset !== undefined ? `byte ${message.offset}` : '');
      console.log(`  ${severity} ${message.code} ${where}: ${message.message}`);
    } else {
      const key = `${severity} ${message.code}`;
      minorCounts.set(key, (minorCounts.get(key) ?? 0) + 1);
    }
  }
  for (const [key, count] of minorCounts) console.log(`  ${key} x${count}`);
  return issues;
}

const args = process.argv.slice(2);
if (args.length === 0) {
  console.error('usage: node validate.mjs FILE_OR_DIR...');
  process.exit(2);
}
let files;
try {
  files = await glbFiles(args);
} catch (error) {
  console.error(`validate.mjs: ${error.message}`);
  process.exit(2);
}
if (files.length === 0) {
  console.error(`validate.mjs: no .glb file in ${args.join(' ')}`);
  process.exit(2);
}

console.log(`gltf-validator ${validator.version()}`);
const totals = { files: 0, failed: 0, errors: 0, warnings: 0, infos: 0, hints: 0 };
for (const file of files) {
  ++totals.files;
  try {
    const issues = await validate(file);
    totals.errors += issues.numErrors;
    totals.warnings += issues.numWarnings;
    totals.infos += issues.numInfos;
    totals.hints += issues.numHints;
    if (issues.numErrors > 0) ++totals.failed;
  } catch (error) {
    // The validator rejects input it cannot even recognise as glTF.
    console.log(`${file}: not validated: ${error}`);
    ++totals.failed;
    ++totals.errors;
  }
}
console.log(`${totals.files} files, ${totals.failed} with errors: ${totals.errors} errors, ` +
            `${totals.warnings} warnings, ${totals.infos} infos, ${totals.hints} hints`);
process.exit(totals.failed > 0 ? 1 : 0);
