// node tools/gltf/validate.mjs FILE.glb...: the Khronos glTF validator on each file. Prints one
// summary line per file ("FILE: E errors, W warnings, I infos, H hints") and every issue under it
// ("  SEVERITY CODE POINTER: MESSAGE"); exits 1 when any file has an error (warnings, infos and
// hints are listed, not failed), 2 when a file cannot be read or is not glTF at all.
import { readFileSync } from 'node:fs';
import validator from 'gltf-validator';

const severities = ['error', 'warning', 'info', 'hint'];
const files = process.argv.slice(2);
if (files.length === 0) {
    console.error('usage: node tools/gltf/validate.mjs FILE.glb...');
    process.exit(2);
}
let status = 0;
for (const file of files) {
    let report;
    try {
        report = await validator.validateBytes(new Uint8Array(readFileSync(file)),
                                               { uri: file, maxIssues: 0, writeTimestamp: false });
    } catch (e) {
        console.error(`${file}: the validator could not read it: ${e}`);
        status = 2;
        continue;
    }
    const i = report.issues;
    console.log(`${file}: ${i.numErrors} errors, ${i.numWarnings} warnings, ${i.numInfos} infos, ${i.numHints} hints`);
    for (const m of i.messages)
        console.log(`  ${severities[m.severity] ?? m.severity} ${m.code} ${m.pointer ?? ''}: ${m.message}`);
    if (i.numErrors > 0 && status === 0) status = 1;
}
process.exit(status);
