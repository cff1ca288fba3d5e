#!/usr/bin/env bash
# Installs what the web page's build and its browser tests (tests/browser.rs) need on Debian 12:
# Debian's Chromium (/usr/bin/chromium, run headless with SwiftShader's WebGPU adapter), the Rust
# target wasm32-unknown-unknown, and wasm-bindgen-cli at the version of the wasm-bindgen crate in
# Cargo.lock (the two must match exactly). Each step is skipped when already done.
set -euo pipefail
cd "$(dirname "$0")/.."
SUDO=""
if [ "$(id -u)" != 0 ]; then SUDO="sudo"; fi

if command -v chromium >/dev/null; then
    echo "chromium already installed: $(chromium --version 2>/dev/null || true)"
else
    export DEBIAN_FRONTEND=noninteractive
    $SUDO apt-get update -qq
    $SUDO apt-get install -y -qq chromium >/dev/null
    echo "installed $(chromium --version 2>/dev/null || echo chromium)"
fi

if rustup target list --installed | grep -qx wasm32-unknown-unknown; then
    echo "rust target wasm32-unknown-unknown already installed"
else
    rustup target add wasm32-unknown-unknown
fi

# The version of the `wasm-bindgen` package in Cargo.lock: the line after `name = "wasm-bindgen"`.
version=$(awk '$0 == "name = \"wasm-bindgen\"" { getline; gsub(/^version = "|"$/, ""); print; exit }' Cargo.lock)
if [ -z "$version" ]; then
    echo "install-browser.sh: no wasm-bindgen package in Cargo.lock" >&2
    exit 1
fi
if [ "$(wasm-bindgen --version 2>/dev/null || true)" = "wasm-bindgen $version" ]; then
    echo "wasm-bindgen $version already installed"
else
    # --locked uses the CLI's own lock file; where the registry lacks one of its pinned versions
    # (webpki-roots 1.0.11 was missing here), resolve afresh: the CLI's version stays exact.
    if ! cargo install wasm-bindgen-cli --version "$version" --locked; then
        echo "install-browser.sh: the locked install failed; retrying without --locked" >&2
        cargo install wasm-bindgen-cli --version "$version"
    fi
    echo "installed $(wasm-bindgen --version)"
fi
