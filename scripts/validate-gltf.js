// node validate-gltf.js FILE...: the Khronos glTF validator's verdict on each file (errors, warnings,
// the first errors); exits 1 when any file has an error. Resources beside a .gltf are read from disk.
const validator = require('gltf-validator');
const fs = require('fs');
const path = require('path');

(async () => {
  let bad = 0;
  for (const file of process.argv.slice(2)) {
    const report = await validator.validateBytes(new Uint8Array(fs.readFileSync(file)), {
      uri: file,
      externalResourceFunction: (uri) => new Promise((resolve, reject) => {
        try {
          resolve(new Uint8Array(fs.readFileSync(path.join(path.dirname(file), decodeURIComponent(uri)))));
        } catch (e) {
          reject(e.toString());
        }
      }),
    });
    const issues = report.issues;
    console.log(`${file}: ${issues.numErrors} errors, ${issues.numWarnings} warnings`);
    for (const m of issues.messages.filter((m) => m.severity === 0).slice(0, 5))
      console.log(`    ${m.code} ${m.pointer || ''} ${m.message}`);
    if (issues.numErrors > 0) bad++;
  }
  console.log(`${process.argv.length - 2 - bad} passed, ${bad} failed`);
  process.exit(bad ? 1 : 0);
})();
