// Decodes ROS 2 CDR messages with Foxglove's own libraries, independently of vifusion's C++ code: each
// message's ros2msg definition is parsed with @foxglove/rosmsg (parse(text, {ros2: true})) and its bytes
// read with @foxglove/rosmsg2-serialization's MessageReader. Proves both the bytes and the definitions.
//
// Usage: node decode_cdr.mjs DIR
//   DIR/manifest.json: [{name, type, cdr, definition}], file names relative to DIR.
// Prints one JSON object on stdout: {NAME: {type, bytes, decoded_bytes, message}} where bytes is the file's
// size and decoded_bytes what the reader consumed. In `message`, 64-bit integers (BigInt) become decimal
// strings and typed arrays plain arrays, so JSON holds every value exactly.

import { readFileSync } from "node:fs";
import { createRequire } from "node:module";
import path from "node:path";

const require = createRequire(import.meta.url);

function loadFoxglove() {
  try {
    return {
      parse: require("@foxglove/rosmsg").parse,
      MessageReader: require("@foxglove/rosmsg2-serialization").MessageReader,
    };
  } catch (error) {
    console.error(`decode_cdr: Foxglove's npm libraries are not installed in tests/node/node_modules ` +
                  `(${error.code ?? error.message}): run .ci/install-deps`);
    process.exit(1);
  }
}

/** The decoded value with BigInts as strings and typed arrays as arrays. */
function plain(value) {
  if (typeof value === "bigint") return value.toString();
  if (ArrayBuffer.isView(value)) return Array.from(value, plain);
  if (Array.isArray(value)) return value.map(plain);
  if (value !== null && typeof value === "object") {
    return Object.fromEntries(Object.entries(value).map(([key, field]) => [key, plain(field)]));
  }
  return value;
}

const directory = process.argv[2];
if (directory === undefined) {
  console.error("usage: node decode_cdr.mjs DIR");
  process.exit(2);
}
const { parse, MessageReader } = loadFoxglove();
const manifest = JSON.parse(readFileSync(path.join(directory, "manifest.json"), "utf8"));
const decoded = {};
for (const entry of manifest) {
  const definition = readFileSync(path.join(directory, entry.definition), "utf8");
  const bytes = readFileSync(path.join(directory, entry.cdr));
  try {
    const reader = new MessageReader(parse(definition, { ros2: true }));
    const message = reader.readMessage(bytes);
    decoded[entry.name] = {
      type: entry.type,
      bytes: bytes.length,
      decoded_bytes: reader.lastReadByteLength(),
      message: plain(message),
    };
  } catch (error) {
    console.error(`decode_cdr: ${entry.name} (${entry.type}): ${error.message}`);
    process.exit(1);
  }
}
process.stdout.write(JSON.stringify(decoded, null, 1) + "\n");
