// Validate glTF files with the Khronos glTF-Validator; prints one JSON report per file
// (one line each: {"file", "numErrors", "numWarnings", "messages": [...]}).
// Usage: node scripts/validate-gltf.mjs FILE.glb [...]
import { readFile } from "node:fs/promises";
import validator from "gltf-validator";

for (const file of process.argv.slice(2)) {
  const report = await validator.validateBytes(new Uint8Array(await readFile(file)), { maxIssues: 100 });
  const { numErrors, numWarnings, messages } = report.issues;
  console.log(JSON.stringify({ file, numErrors, numWarnings, messages }));
}
