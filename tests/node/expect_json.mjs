// Compares two JSON files value by value: objects must have the same keys, arrays the same length, numbers,
// strings and booleans must be identical (no tolerance: the writer printed doubles with 17 digits).
// Prints every difference with its path and exits 1 if there is any.
//
// Usage: node expect_json.mjs EXPECTED.json ACTUAL.json [--tolerance PATH=ABS]...
//
// --tolerance lets numbers whose path starts with PATH (e.g. '$.ground_truth') differ by up to ABS, for
// values that EXPECTED.json only has rounded (a text file's fixed decimals); the largest difference seen is
// printed. Everything else stays exact.

import { readFileSync } from "node:fs";

const usage = "usage: node expect_json.mjs EXPECTED.json ACTUAL.json [--tolerance PATH=ABS]...";
const [expectedPath, actualPath, ...options] = process.argv.slice(2);
if (actualPath === undefined) {
  console.error(usage);
  process.exit(2);
}
const tolerances = [];
for (let i = 0; i < options.length; ++i) {
  const match = options[i] === "--tolerance" ? /^(.+)=(.+)$/.exec(options[i + 1] ?? "") : null;
  const absolute = match ? Number(match[2]) : NaN;
  if (!(absolute >= 0)) {
    console.error(usage);
    process.exit(2);
  }
  tolerances.push({ prefix: match[1], absolute, compared: 0, largest: 0 });
  ++i;
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
  const tolerance = kind(want) === "number" ? tolerances.find((t) => where.startsWith(t.prefix)) : undefined;
  if (tolerance) {
    const difference = Math.abs(want - got);
    ++tolerance.compared;
    tolerance.largest = Math.max(tolerance.largest, difference);
    if (!(difference <= tolerance.absolute)) {
      differences.push(`${where}: expected ${want} within ${tolerance.absolute}, got ${got} (off by ${difference})`);
    }
    return;
  }
  if (want !== got) differences.push(`${where}: expected ${JSON.stringify(want)}, got ${JSON.stringify(got)}`);
}

compare(expected, actual, "$");
if (differences.length > 0) {
  console.error(`${differences.length} difference(s) between ${expectedPath} and ${actualPath}:`);
  for (const difference of differences) console.error(`  ${difference}`);
  process.exit(1);
}
const within = tolerances.map((t) => `, ${t.compared} of them under ${t.prefix} within ${t.absolute} (largest difference ${t.largest})`);
console.log(`${Object.keys(expected).length} messages, ${compared} values agree${within.join("")}`);
