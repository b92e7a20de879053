// SPDX-License-Identifier: BSD-3-Clause
// Runs the Khronos glTF validator (npm package gltf-validator, installed by
// .ci/install-npm-tools.sh) on every file given; prints each file's counts and every error
// and warning; exit code 1 when any file has an error, 2 when the validator cannot run.
//   NODE_PATH=<prefix>/node_modules node validate-gltf.js a.glb b.gltf ...
'use strict';
const fs = require('fs');
const path = require('path');
const validator = require('gltf-validator');

const severities = ['error', 'warning', 'info', 'hint'];

async function validate(file) {
  const bytes = new Uint8Array(fs.readFileSync(file));
  const report = await validator.validateBytes(bytes, {
    uri: path.basename(file),
    maxIssues: 0, // all of them
    externalResourceFunction: (uri) => new Promise((resolve, reject) => {
      fs.readFile(path.resolve(path.dirname(file), decodeURIComponent(uri)),
        (err, data) => (err ? reject(err.toString()) : resolve(new Uint8Array(data))));
    }),
  });
  const issues = report.issues;
  console.log(`${file}: ${issues.numErrors} errors, ${issues.numWarnings} warnings, ` +
    `${issues.numInfos} infos, ${issues.numHints} hints (gltf-validator ${report.validatorVersion})`);
  for (const m of issues.messages) {
    if (m.severity <= 1) {
      console.log(`  ${severities[m.severity]} ${m.code} ${m.pointer || ''}: ${m.message}`);
    }
  }
  return issues.numErrors;
}

(async () => {
  const files = process.argv.slice(2);
  if (files.length === 0) {
    console.error('validate-gltf.js: no files given');
    process.exit(2);
  }
  let failed = 0;
  for (const file of files) {
    if ((await validate(file)) > 0) {
      failed += 1;
    }
  }
  process.exit(failed > 0 ? 1 : 0);
})().catch((e) => {
  console.error(`validate-gltf.js: ${e}`);
  process.exit(2);
});
