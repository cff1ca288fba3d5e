#!/usr/bin/env bash
# Builds the web page into web/dist/: the library and web/src compiled for wasm32 (release),
# wasm-bindgen's JavaScript bindings, and the page's own files. Needs the wasm32-unknown-unknown
# target and wasm-bindgen-cli at the version of Cargo.lock (.ci/install-browser.sh installs
# both). Its own target folder (target/web) lets it run while another cargo holds target/.
set -euo pipefail
cd "$(dirname "$0")/.."
target_dir="${CARGO_TARGET_DIR:-$PWD/target}/web"
cargo build -p raygraph-web --target wasm32-unknown-unknown --release --target-dir "$target_dir"
mkdir -p web/dist
wasm-bindgen --target web --no-typescript --out-dir web/dist "$target_dir/wasm32-unknown-unknown/release/raygraph_web.wasm"
cp web/index.html web/app.js web/style.css web/dist/
echo "built web/dist (serve it: python3 -m http.server -d web/dist 8080)"
