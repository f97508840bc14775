// Compares two JSON files value by value: objects must have the same keys, arrays the same length, numbers,
// strings and booleans must be identical (no tolerance: the writer printed doubles with 17 digits).
// Prints every difference with its path and exits 1 if there is any.
//
// Usage: node expect_json.mjs EXPECTED.json ACTUAL.json

import { readFileSync } from "node:fs";

const [expectedPath, actualPath] = process.argv.slice(2);
if (actualPath === undefined) {
  console.error("usage: node expect_json.mjs EXPECTED.json ACTUAL.json");
  process.exit(2);
}
const expected = JSON.parse(readFileSync(expectedPath, "utf8"));
const actual = JSON.parse(readFileSync(actualPath, "utf8"));

const differences = [];
let compared = 0;

function kind(value) {
  if (value === null) return "null";
  return Array.isArray(value) ? "array" : typeof value;
}

function compare(want, got, where) {
  if (kind(want) !== kind(got)) {
    differences.push(`${where}: expected ${kind(want)} ${JSON.stringify(want)}, got ${kind(got)} ${JSON.stringify(got)}`);
    return;
  }
  if (kind(want) === "array") {
    if (want.length !== got.length) {
      differences.push(`${where}: expected ${want.length} elements, got ${got.length}`);
      return;
    }
    want.forEach((element, index) => compare(element, got[index], `${where}[${index}]`));
    return;
  }
  if (kind(want) === "object") {
    for (const key of Object.keys(want)) {
      if (!(key in got)) differences.push(`${where}.${key}: missing`);
      else compare(want[key], got[key], `${where}.${key}`);
    }
    for (const key of Object.keys(got)) {
      if (!(key in want)) differences.push(`${where}.${key}: not expected (${JSON.stringify(got[key])})`);
    }
    return;
  }
  ++compared;
  if (want !== got) differences.push(`${where}: expected ${JSON.stringify(want)}, got ${JSON.stringify(got)}`);
}

compare(expected, actual, "$");
if (differences.length > 0) {
  console.error(`${differences.length} difference(s) between ${expectedPath} and ${actualPath}:`);
  for (const difference of differences) console.error(`  ${difference}`);
  process.exit(1);
}
console.log(`${Object.keys(expected).length} messages, ${compared} values agree`);
