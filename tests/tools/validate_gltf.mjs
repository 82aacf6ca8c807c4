// Validate a glTF/GLB file with the Khronos glTF validator and print its report as JSON.
// Usage: node validate_gltf.mjs FILE  (exit 0 when the report was printed, 2 on a usage or read error)
import { readFile } from "node:fs/promises";
import path from "node:path";
import validator from "gltf-validator";

const file = process.argv[2];
if (!file) {
  process.stderr.write("usage: node validate_gltf.mjs FILE.glb|FILE.gltf\n");
  process.exit(2);
}
try {
  const data = await readFile(file);
  const dir = path.dirname(file);
  const report = await validator.validateBytes(new Uint8Array(data), {
    uri: path.basename(file),
    maxIssues: 0,
    externalResourceFunction: (uri) =>
      readFile(path.resolve(dir, decodeURIComponent(uri))).then((b) => new Uint8Array(b)),
  });
  process.stdout.write(JSON.stringify(report, null, 2) + "\n");
} catch (err) {
  process.stderr.write(`validate_gltf: ${file}: ${err}\n`);
  process.exit(2);
}
