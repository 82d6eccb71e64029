// Copies the preview page of `qcsg view` (crates/qcsg-cli/src/view/assets/) into media/, so the
// panel shows the very page the browser shows. Run by `npm run build`.
const fs = require("fs");
const path = require("path");

const from = path.join(__dirname, "..", "..", "..", "crates", "qcsg-cli", "src", "view", "assets");
const to = path.join(__dirname, "..", "media");
fs.mkdirSync(to, { recursive: true });
for (const name of ["index.html", "view.js", "view.css"]) {
  fs.copyFileSync(path.join(from, name), path.join(to, name));
}
