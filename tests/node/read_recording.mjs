#!/usr/bin/env node
// Reads a vifusion recording (drivers/recording/include/vifusion/recording/topics.hpp) with Foxglove's own
// libraries only — @mcap/core's McapIndexedReader for the container, @foxglove/rosmsg's parser on the schema
// definitions the file carries and @foxglove/rosmsg2-serialization's MessageReader for the CDR payloads —
// checks what a ROS 2 tool relies on, and prints what it decoded as the JSON that
// tests/recording/print_dataset_expectation prints from the dataset the recording was made from:
//
//   {"calibration": {"fx", "fy", "cx", "cy"}, "frames": [...], "imu": [...], "ground_truth": [...]}
//
// Checks (the exit code is 1 with every failure listed on stderr):
//   - every channel's message encoding is "cdr", its schema's encoding "ros2msg", and its topic has the
//     schema name topics.hpp gives it (no topic outside that list);
//   - every message decodes, consuming all of its bytes, and its MCAP publish time equals its header stamp;
//   - the fixed messages (recording info, both camera infos, /tf_static) come once each;
//   - each frame has its stamps, a 16UC1 depth and an rgb8 colour image with one stamp, in that order;
//   - the attachment calibration.yaml is the RecordingInfo's calibration_yaml, character for character.
//
// Usage: node read_recording.mjs FILE.mcap > actual.json

import { open } from "node:fs/promises";
import { createRequire } from "node:module";

const require = createRequire(import.meta.url);
const installHint = "run .ci/install-deps (it runs npm ci in tests/node)";

let McapIndexedReader, parse, MessageReader;
try {
  ({ McapIndexedReader } = require("@mcap/core"));
  ({ parse } = require("@foxglove/rosmsg"));
  ({ MessageReader } = require("@foxglove/rosmsg2-serialization"));
} catch (error) {
  console.error(`read_recording.mjs: Foxglove's npm libraries are not in tests/node/node_modules ` +
                `(${error.code ?? error.message}): ${installHint}`);
  process.exit(1);
}

// topics.hpp: topic → ROS 2 type (MCAP Schema.name).
const kSchemaOfTopic = new Map([
  ["/vifusion/recording_info", "vifusion_msgs/msg/RecordingInfo"],
  ["/camera/color/camera_info", "sensor_msgs/msg/CameraInfo"],
  ["/camera/depth/camera_info", "sensor_msgs/msg/CameraInfo"],
  ["/tf_static", "tf2_msgs/msg/TFMessage"],
  ["/vifusion/frame_stamps", "vifusion_msgs/msg/FrameStamps"],
  ["/camera/depth/image_rect_raw", "sensor_msgs/msg/Image"],
  ["/camera/color/image_raw", "sensor_msgs/msg/Image"],
  ["/camera/imu", "sensor_msgs/msg/Imu"],
  ["/vifusion/sync_edges", "vifusion_msgs/msg/SyncEdge"],
  ["/vifusion/clock", "vifusion_msgs/msg/ClockMapping"],
  ["/vifusion/motion_packets", "vifusion_msgs/msg/MotionPacket"],
  ["/ground_truth/camera_pose", "geometry_msgs/msg/TransformStamped"],
]);
const kOnceTopics = ["/vifusion/recording_info", "/camera/color/camera_info", "/camera/depth/camera_info", "/tf_static"];
const kCalibrationAttachment = "calibration.yaml";
const kNsPerSecond = 1000000000n;
// FNV-1a, 32 bits (tests/recording/fnv1a.hpp).
const kFnvOffsetBasis = 0x811c9dc5;
const kFnvPrime = 0x01000193;

const problems = [];
const problem = (text) => {
  if (problems.length < 50) problems.push(text);
};

function fnv1a32(bytes, hash = kFnvOffsetBasis) {
  for (let i = 0; i < bytes.length; ++i) hash = Math.imul(hash ^ bytes[i], kFnvPrime) >>> 0;
  return hash;
}

/** A builtin_interfaces/Time as ns (BigInt); MessageReader names the second field nanosec (ROS 2) or nsec. */
function stampNs(time) {
  return BigInt(time.sec) * kNsPerSecond + BigInt(time.nanosec ?? time.nsec);
}

/** The header stamp a message's publish time must equal: its own header's, or (TFMessage) every transform's. */
function headerStamps(message) {
  if (message.header) return [stampNs(message.header.stamp)];
  if (message.transforms) return message.transforms.map((t) => stampNs(t.header.stamp));
  return [];
}

/** Hash of an image's pixel bytes, row by row without the row padding (step − width · bytes per pixel). */
function imageHash(image, encoding, bytesPerPixel, where) {
  if (image.encoding !== encoding) problem(`${where}: encoding '${image.encoding}', expected '${encoding}'`);
  if (image.is_bigendian !== 0) problem(`${where}: is_bigendian ${image.is_bigendian}, expected 0`);
  const rowBytes = image.width * bytesPerPixel;
  if (image.step < rowBytes || image.data.length !== image.step * image.height) {
    problem(`${where}: step ${image.step} and ${image.data.length} bytes for ${image.width}x${image.height}`);
    return 0;
  }
  let hash = kFnvOffsetBasis;
  for (let y = 0; y < image.height; ++y) hash = fnv1a32(image.data.subarray(y * image.step, y * image.step + rowBytes), hash);
  return hash;
}

async function readRecording(path) {
  const handle = await open(path, "r");
  try {
    const size = BigInt((await handle.stat()).size);
    const readable = {
      size: async () => size,
      read: async (offset, length) => {
        const buffer = new Uint8Array(Number(length));
        const { bytesRead } = await handle.read(buffer, 0, buffer.byteLength, Number(offset));
        if (bytesRead !== buffer.byteLength) throw new Error(`${path}: short read at ${offset}`);
        return buffer;
      },
    };
    const reader = await McapIndexedReader.Initialize({ readable });
    if (reader.header.profile !== "ros2") problem(`header profile '${reader.header.profile}', expected 'ros2'`);

    // One MessageReader per channel, from the definition the file itself carries.
    const decoders = new Map();
    const text = new TextDecoder("utf-8", { fatal: true });
    for (const [id, channel] of reader.channelsById) {
      const schema = reader.schemasById.get(channel.schemaId);
      const where = `channel ${id} '${channel.topic}'`;
      if (channel.messageEncoding !== "cdr") problem(`${where}: message encoding '${channel.messageEncoding}', expected 'cdr'`);
      if (!kSchemaOfTopic.has(channel.topic)) problem(`${where}: not a topic of topics.hpp`);
      if (!schema) {
        problem(`${where}: no schema (id ${channel.schemaId})`);
        continue;
      }
      if (schema.encoding !== "ros2msg") problem(`${where}: schema encoding '${schema.encoding}', expected 'ros2msg'`);
      if (kSchemaOfTopic.has(channel.topic) && schema.name !== kSchemaOfTopic.get(channel.topic)) {
        problem(`${where}: schema '${schema.name}', expected '${kSchemaOfTopic.get(channel.topic)}'`);
      }
      decoders.set(id, { topic: channel.topic, reader: new MessageReader(parse(text.decode(schema.data), { ros2: true })) });
    }

    const out = { calibration: undefined, frames: [], imu: [], ground_truth: [] };
    const counts = new Map();
    let info;
    let pending;  // the frame whose stamps came and whose images are awaited
    for await (const record of reader.readMessages({ validateCrcs: true })) {
      const decoder = decoders.get(record.channelId);
      if (!decoder) continue;  // already reported
      const { topic } = decoder;
      const where = `${topic} #${record.sequence} (log time ${record.logTime})`;
      counts.set(topic, (counts.get(topic) ?? 0) + 1);
      let message;
      try {
        message = decoder.reader.readMessage(record.data);
      } catch (error) {
        problem(`${where}: does not decode: ${error.message}`);
        continue;
      }
      if (decoder.reader.lastReadByteLength() !== record.data.byteLength) {
        problem(`${where}: decoding used ${decoder.reader.lastReadByteLength()} of ${record.data.byteLength} bytes`);
      }
      const stamps = headerStamps(message);
      if (stamps.length === 0) problem(`${where}: no header stamp`);
      for (const stamp of stamps) {
        if (stamp !== record.publishTime) problem(`${where}: publish time ${record.publishTime} but header stamp ${stamp}`);
      }
      const t_ns = stamps.length > 0 ? stamps[0].toString() : "";

      switch (topic) {
        case "/vifusion/recording_info":
          info = message;
          break;
        case "/camera/color/camera_info":
          out.calibration = { fx: message.k[0], fy: message.k[4], cx: message.k[2], cy: message.k[5] };
          break;
        case "/vifusion/frame_stamps":
          if (pending) problem(`${where}: frame ${pending.index} before it has no image of each kind`);
          pending = { t_ns, index: Number(message.index) };
          break;
        case "/camera/depth/image_rect_raw":
        case "/camera/color/image_raw": {
          const depth = topic === "/camera/depth/image_rect_raw";
          if (!pending || pending.t_ns !== t_ns || (depth ? pending.depth || pending.rgb : !pending.depth || pending.rgb)) {
            problem(`${where}: image stamped ${t_ns} out of order (frame stamps, depth, colour)`);
            break;
          }
          const hash = depth ? imageHash(message, "16UC1", 2, where) : imageHash(message, "rgb8", 3, where);
          pending[depth ? "depth" : "rgb"] = { width: message.width, height: message.height, fnv1a32: hash };
          if (!depth) {
            out.frames.push(pending);
            pending = undefined;
          }
          break;
        }
        case "/camera/imu": {
          const w = message.angular_velocity;
          const a = message.linear_acceleration;
          out.imu.push({ t_ns, gyro_rad_s: [w.x, w.y, w.z], accel_mps2: [a.x, a.y, a.z] });
          break;
        }
        case "/ground_truth/camera_pose": {
          const p = message.transform.translation;
          const q = message.transform.rotation;
          out.ground_truth.push({ t_ns, p_m: [p.x, p.y, p.z], q_xyzw: [q.x, q.y, q.z, q.w] });
          break;
        }
        default:
          break;
      }
    }
    if (pending) problem(`the last frame (index ${pending.index}) has no image of each kind`);
    for (const topic of kOnceTopics) {
      if (counts.get(topic) !== 1) problem(`${topic}: ${counts.get(topic) ?? 0} messages, expected 1`);
    }

    const attachments = [];
    for await (const attachment of reader.readAttachments({ validateCrcs: true })) attachments.push(attachment);
    const calibration = attachments.filter((a) => a.name === kCalibrationAttachment);
    if (calibration.length !== 1) {
      problem(`${calibration.length} attachments named ${kCalibrationAttachment}, expected 1`);
    } else if (!info) {
      problem("no recording info to compare the calibration attachment with");
    } else if (text.decode(calibration[0].data) !== info.calibration_yaml) {
      problem(`attachment ${kCalibrationAttachment} (${calibration[0].data.byteLength} bytes) differs from ` +
              `RecordingInfo.calibration_yaml (${info.calibration_yaml.length} characters)`);
    }
    return out;
  } finally {
    await handle.close();
  }
}

const path = process.argv[2];
if (path === undefined || process.argv.length !== 3) {
  console.error("usage: node read_recording.mjs FILE.mcap > actual.json");
  process.exit(2);
}
try {
  const decoded = await readRecording(path);
  process.stdout.write(JSON.stringify(decoded) + "\n");
} catch (error) {
  problem(`${path}: ${error.message}`);
}
if (problems.length > 0) {
  console.error(`read_recording.mjs: ${path}:\n  ${problems.join("\n  ")}`);
  process.exit(1);
}
console.error(`read_recording.mjs: ${path}: every channel, schema, stamp and the calibration attachment check out`);
