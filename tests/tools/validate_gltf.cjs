// Validates glTF 2.0 files with the Khronos glTF validator (the `gltf-validator`
// npm package): node validate_gltf.cjs VALIDATOR_DIR FILE... prints each
// file's error/warning/info counts and every message, and exits 1 when any
// file has an error (or cannot be read). External resources (.bin, textures)
// are loaded from beside each file.
"use strict";
const fs = require("fs");
const path = require("path");

const [validatorDir, ...files] = process.argv.slice(2);
if (!validatorDir || files.length === 0) {
    console.error("usage: node validate_gltf.cjs VALIDATOR_DIR FILE...");
    process.exit(2);
}
const validator = require(path.resolve(validatorDir));

async function validate(file) {
    const bytes = fs.readFileSync(file);
    const report = await validator.validateBytes(new Uint8Array(bytes), {
        uri: path.basename(file),
        maxIssues: 100,
        externalResourceFunction: (uri) =>
            new Promise((resolve, reject) => {
                const resource = path.resolve(path.dirname(file), decodeURIComponent(uri));
                fs.readFile(resource, (error, data) => (error ? reject(error.toString()) : resolve(new Uint8Array(data))));
            }),
    });
    const issues = report.issues;
    console.log(
        `${file}: ${issues.numErrors} errors, ${issues.numWarnings} warnings, ${issues.numInfos} infos, ` +
            `${issues.numHints} hints (validator ${report.validatorVersion})`,
    );
    for (const message of issues.messages) {
        const severity = ["error", "warning", "info", "hint"][message.severity] || message.severity;
        console.log(`  ${severity} ${message.code} at ${message.pointer || message.offset || "-"}: ${message.message}`);
    }
    return issues.numErrors;
}

(async () => {
    let errors = 0;
    for (const file of files) {
        try {
            errors += await validate(file);
        } catch (error) {
            console.log(`${file}: could not be validated: ${error}`);
            errors += 1;
        }
    }
    process.exit(errors > 0 ? 1 : 0);
})();
