#!/bin/sh
# Creates the Python environment of the report's peers (Manifold and build123d), pinned, under
# the workspace's target folder, where `qcsg-bench` looks for it:
#     sh crates/qcsg-bench/peers/setup.sh
set -e
root=$(cd "$(dirname "$0")/../../.." && pwd)
venv="$root/target/qcsg-bench-peers/venv"
python3 -m venv "$venv"
"$venv/bin/pip" install --quiet -r "$(dirname "$0")/requirements.txt"
echo "peers installed in $venv"
