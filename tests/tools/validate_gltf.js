// Runs the Khronos glTF validator on a .gltf or .glb file and prints a one-line summary:
//   errors=<n> warnings=<n> infos=<n> hints=<n>
// followed by the messages of every error and warning. Exit code 0 when the report was made.
// Usage: node validate_gltf.js <file> <node_modules folder holding gltf-validator>
const fs = require('fs');
const path = require('path');
const file = process.argv[2];
const modules = process.argv[3];
const validator = require(path.join(modules, 'gltf-validator'));

const bytes = new Uint8Array(fs.readFileSync(file));
validator.validateBytes(bytes, {
    uri: path.basename(file),
    maxIssues: 100,
    externalResourceFunction: (uri) => new Promise((resolve, reject) => {
        fs.readFile(path.join(path.dirname(file), decodeURIComponent(uri)), (err, data) => {
            if (err) reject(err.toString()); else resolve(new Uint8Array(data));
        });
    }),
}).then((report) => {
    const i = report.issues;
    console.log(`errors=${i.numErrors} warnings=${i.numWarnings} infos=${i.numInfos} hints=${i.numHints}`);
    for (const m of i.messages)
        if (m.severity <= 1) console.log(`${m.severity === 0 ? 'error' : 'warning'} ${m.code} ${m.pointer || ''}: ${m.message}`);
}).catch((error) => {
    console.log('errors=1 warnings=0 infos=0 hints=0');
    console.log('error VALIDATOR_FAILED: ' + error);
});
