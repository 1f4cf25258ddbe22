#!/usr/bin/env node
// Validates glTF/GLB files with the Khronos glTF validator (npm's gltf-validator, installed by
// tools/install-deps from package-lock.json). Prints every issue with its severity, code and JSON
// pointer; exits 1 when any file has an error (warnings and hints are printed, not fatal), 2 on a
// usage or setup problem.
//   node tools/gltf-validate.js FILE.glb...
'use strict';

const fs = require('fs');
const path = require('path');

const SEVERITY = ['error', 'warning', 'info', 'hint'];

function usage(stream) {
  stream.write('usage: node tools/gltf-validate.js FILE.glb|FILE.gltf...\n' +
               'Validates each file with the Khronos glTF validator; exit 1 if any has an error.\n');
}

function loadValidator() {
  try {
    return require('gltf-validator');
  } catch (e) {
    process.stderr.write('gltf-validate: the npm package gltf-validator is not installed (' +
                         e.code + '); run tools/install-deps (it runs `npm ci`)\n');
    process.exit(2);
  }
}

async function validateFile(validator, file) {
  let bytes;
  try {
    bytes = fs.readFileSync(file);
  } catch (e) {
    process.stderr.write(`${file}: cannot read: ${e.message}\n`);
    return false;
  }
  // External resources are refused: the project's assets are self-contained .glb files.
  const report = await validator.validateBytes(new Uint8Array(bytes), {
    uri: path.basename(file),
    maxIssues: 1000,
    externalResourceFunction: (uri) => Promise.reject(new Error(`external resource ${uri}`)),
  });
  const issues = report.issues;
  for (const m of issues.messages) {
    process.stdout.write(`${file}: ${SEVERITY[m.severity] || m.severity}: ${m.code}` +
                         `${m.pointer ? ' at ' + m.pointer : ''}: ${m.message}\n`);
  }
  process.stdout.write(`${file}: ${issues.numErrors} errors, ${issues.numWarnings} warnings, ` +
                       `${issues.numInfos} infos, ${issues.numHints} hints ` +
                       `(gltf-validator ${report.validatorVersion})\n`);
  return issues.numErrors === 0;
}

async function main(args) {
  if (args.length === 0 || args.includes('-h') || args.includes('--help')) {
    usage(args.length === 0 ? process.stderr : process.stdout);
    process.exit(args.length === 0 ? 2 : 0);
  }
  const validator = loadValidator();
  let ok = true;
  for (const file of args) {
    ok = (await validateFile(validator, file)) && ok;
  }
  process.exit(ok ? 0 : 1);
}

main(process.argv.slice(2)).catch((e) => {
  process.stderr.write(`gltf-validate: ${e && e.message ? e.message : e}\n`);
  process.exit(2);
});
