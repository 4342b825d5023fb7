#!/usr/bin/env node
// A first learner in JavaScript (Node.js, no packages): dead reckoning with the
// command as the velocity (A0), and a straight-line sensor model fitted to it by
// least squares over every reading. The protocol is JSON lines on stdin and
// stdout (book: "The process protocol"); logs go to stderr.
//
//   cargo run --release --example train -- --learner 'exec:node examples/learners/quickstart.js'
"use strict";
const readline = require("readline");

const send = (m) => process.stdout.write(JSON.stringify(m) + "\n");
send({ type: "hello", protocol: 1, name: "quickstart-js",
       about: "dead reckoning with A0, a straight-line sensor model by least squares", settings: [] });

let x = 0, n = 0, su = 0, sx = 0, suu = 0, sux = 0;
function sensorModel() {
  const det = n * suu - su * su;
  if (n < 2 || det <= 1e-9 * Math.max(1, n * suu)) return null; // not yet
  const s1 = (n * sux - su * sx) / det;
  return [(sx - s1 * su) / n, s1];
}

const lines = readline.createInterface({ input: process.stdin });
lines.on("line", (line) => {
  const m = JSON.parse(line);
  switch (m.type) {
    case "settings": break; // none of its own; the shared ones are not needed
    case "command": x += m.command * m.dt_s; break;
    case "reading":
      n += 1; su += m.obs_px; sx += x; suu += m.obs_px * m.obs_px; sux += m.obs_px * x;
      break;
    case "query":
      send({ type: "models", action: [0, 1], sensor: sensorModel(), x_a: x, x_s: null });
      break;
    case "end": process.exit(0);
    default: send({ type: "error", message: `unknown message type ${m.type}` }); process.exit(1);
  }
});
