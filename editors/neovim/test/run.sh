#!/usr/bin/env bash
# Headless Neovim test of this configuration against the qcsg language server:
# opens a file with an error, checks the diagnostic from `qcsg lsp` and a hover.
# Usage: editors/neovim/test/run.sh path/to/qcsg   (needs nvim 0.7 or later on PATH)
set -euo pipefail

qcsg="$(realpath "${1:?usage: $0 path/to/qcsg}")"
test_dir="$(cd "$(dirname "$0")" && pwd)"
plugin_dir="$(dirname "$test_dir")"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

export QCSG_BIN="$qcsg" QCSG_TEST_DIR="$work"
# -u NONE: no user configuration; the plugin directory is put on 'runtimepath' by hand.
timeout 120 nvim --headless -u NONE -i NONE -n \
    --cmd "set runtimepath^=$plugin_dir" --cmd "filetype on" --cmd "syntax on" \
    -c "luafile $test_dir/lsp_test.lua"
