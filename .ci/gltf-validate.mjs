// Validates every .glb under the directories given on the command line with
// the Khronos glTF validator (npm package `gltf-validator`); prints each
// file's error, warning, info and hint counts and the messages of errors and
// warnings, and exits non-zero if any file has an error.
//
//   node .ci/gltf-validate.mjs DIR...    (NODE_PATH or a local install must provide gltf-validator)
import { readFileSync, readdirSync, statSync } from "node:fs";
import { join } from "node:path";
import { createRequire } from "node:module";

const require = createRequire(join(process.cwd(), "target", "ci-node", "package.json"));
const validator = require("gltf-validator");

function glbs(dir) {
  let out = [];
  for (const name of readdirSync(dir)) {
    const p = join(dir, name);
    if (statSync(p).isDirectory()) out = out.concat(glbs(p));
    else if (name.endsWith(".glb")) out.push(p);
  }
  return out;
}

const dirs = process.argv.slice(2);
if (dirs.length === 0) {
  console.error("usage: node .ci/gltf-validate.mjs DIR...");
  process.exit(2);
}
const files = dirs.flatMap(glbs).sort();
if (files.length === 0) {
  console.error(`no .glb files under ${dirs.join(", ")}`);
  process.exit(1);
}
let failed = 0;
for (const file of files) {
  const report = await validator.validateBytes(new Uint8Array(readFileSync(file)), {
    uri: file,
    maxIssues: 100,
  });
  const n = report.issues;
  console.log(
    `${file}: ${n.numErrors} errors, ${n.numWarnings} warnings, ${n.numInfos} infos, ${n.numHints} hints`,
  );
  for (const m of n.messages) {
    const kind = ["error", "warning", "info", "hint"][m.severity] ?? m.severity;
    console.log(`  ${kind} ${m.code} ${m.pointer ?? ""}: ${m.message}`);
  }
  if (n.numErrors > 0) failed += 1;
}
if (failed > 0) {
  console.error(`${failed} of ${files.length} glTF file(s) have errors`);
  process.exit(1);
}
console.log(`${files.length} glTF file(s) valid`);
