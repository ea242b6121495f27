#!/usr/bin/env node
// Validates glTF 2.0 files (.gltf or .glb) with the Khronos glTF Validator, the npm package
// gltf-validator at the exact version pinned in tools/package.json, installed into
// tools/node_modules/ by scripts/setup.sh (npm ci --prefix tools).
//
//   node scripts/validate-gltf.mjs FILE...          validate; exit 0 when no file has an error or
//                                                   a warning, 1 when one has, 2 on a usage error
//                                                   or when the validator is not installed
//   node scripts/validate-gltf.mjs --check-installed  exit 0 when the pinned version is installed
//
// What fails: any message of severity Error or Warning. Infos and hints (a degenerate triangle
// that a test scene holds on purpose, an object nothing uses) are printed but do not fail.
// A failing file gets every message printed, with its JSON pointer; a passing one a single line.
import { createRequire } from 'node:module';
import { readFile } from 'node:fs/promises';
import { existsSync, readFileSync } from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const repo = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..');
const toolsDir = path.join(repo, 'tools');
const pinned = JSON.parse(readFileSync(path.join(toolsDir, 'package.json'), 'utf8')).dependencies['gltf-validator'];
const installHint =
  `install it with scripts/setup.sh, or: npm ci --prefix ${toolsDir} (needs npm and the npm registry)`;

function loadValidator() {
  const packageJson = path.join(toolsDir, 'node_modules', 'gltf-validator', 'package.json');
  if (!existsSync(packageJson)) return { error: `gltf-validator ${pinned} is not installed in ${toolsDir}/node_modules; ${installHint}` };
  const installed = JSON.parse(readFileSync(packageJson, 'utf8')).version;
  if (installed !== pinned)
    return { error: `gltf-validator ${installed} is installed in ${toolsDir}/node_modules but tools/package.json pins ${pinned}; ${installHint}` };
  const require = createRequire(path.join(toolsDir, 'package.json'));
  return { validator: require('gltf-validator') };
}

const kSeverity = ['error', 'warning', 'info', 'hint'];

function where(message) {
  if (message.pointer !== undefined) return ` at ${message.pointer}`;
  if (message.offset !== undefined) return ` at byte ${message.offset}`;
  return '';
}

async function validate(validator, file) {
  const bytes = new Uint8Array(await readFile(file));
  return validator.validateBytes(bytes, {
    uri: file,
    maxIssues: 0,  // every message, not the first 100
    writeTimestamp: false,
    // External buffers and images (a .gltf beside its .bin, Sponza's textures) are read and
    // checked too; ours embed everything.
    externalResourceFunction: (uri) =>
      readFile(path.resolve(path.dirname(file), decodeURIComponent(uri))).then((b) => new Uint8Array(b)),
  });
}

async function main(args) {
  const check = args.includes('--check-installed');
  const files = args.filter((a) => a !== '--check-installed');
  const { validator, error } = loadValidator();
  if (error) {
    console.error(`validate-gltf: ${error}`);
    return 2;
  }
  if (check) {
    console.log(`gltf-validator ${validator.version()} (pinned ${pinned})`);
    return 0;
  }
  if (files.length === 0) {
    console.error('usage: node scripts/validate-gltf.mjs FILE.gltf|FILE.glb... (or --check-installed)');
    return 2;
  }
  let failed = 0;
  for (const file of files) {
    let report;
    try {
      report = await validate(validator, file);
    } catch (e) {  // unreadable file or not glTF/GLB at all
      console.log(`FAIL ${file}: the validator could not read it: ${e}`);
      ++failed;
      continue;
    }
    const { numErrors, numWarnings, numInfos, numHints, messages } = report.issues;
    const counts = `${numErrors} errors, ${numWarnings} warnings, ${numInfos} infos, ${numHints} hints`;
    const bad = numErrors > 0 || numWarnings > 0;
    if (bad) ++failed;
    const codes = [...new Set(messages.filter((m) => m.severity >= 2).map((m) => m.code))];
    console.log(`${bad ? 'FAIL' : 'ok  '} ${file}: ${counts}${!bad && codes.length ? ` (${codes.join(', ')})` : ''}`);
    if (bad)
      for (const m of messages) console.log(`  ${kSeverity[m.severity] ?? m.severity} ${m.code}${where(m)}: ${m.message}`);
  }
  console.log(`gltf-validator ${validator.version()}: ${files.length - failed} of ${files.length} files have no errors or warnings`);
  return failed > 0 ? 1 : 0;
}

process.exitCode = await main(process.argv.slice(2));
