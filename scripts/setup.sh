#!/usr/bin/env bash
# Makes sure this machine has what underlight needs to build and run:
#   - Rust (cargo), and a C++ toolchain to link the static shader compiler;
#   - the Vulkan loader, Mesa's lavapipe driver, the Khronos validation layers, vulkaninfo;
#   - libshaderc-dev (static glslang/SPIRV-Tools, linked by build.rs) and spirv-tools (spirv-val);
#   - xvfb, for the viewer's tests on a machine without a display;
#   - fonts-dejavu-core, the font `underlight sweep` labels its plot with.
# As root on Debian/Ubuntu it installs missing packages with apt-get; otherwise it prints the
# exact command to run and exits non-zero.
set -euo pipefail

PACKAGES=(g++ pkg-config libvulkan1 mesa-vulkan-drivers vulkan-validationlayers vulkan-tools
          libshaderc-dev spirv-tools xvfb fonts-dejavu-core)

if ! command -v dpkg-query >/dev/null 2>&1 || ! command -v apt-get >/dev/null 2>&1; then
  echo "underlight's setup script knows Debian/Ubuntu only. Install the equivalents of:" >&2
  echo "  ${PACKAGES[*]}" >&2
  exit 1
fi

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -gt 0 ]; then
  if [ "$(id -u)" -eq 0 ]; then
    echo "setup: installing ${missing[*]}"
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -qq
    apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
  else
    echo "underlight needs these packages: ${missing[*]}" >&2
    echo "Install them with:" >&2
    echo "  sudo apt-get update && sudo apt-get install -y --no-install-recommends ${missing[*]}" >&2
    exit 1
  fi
fi

if ! command -v cargo >/dev/null 2>&1; then
  if [ -x "$HOME/.cargo/bin/cargo" ]; then
    export PATH="$HOME/.cargo/bin:$PATH"
  else
    echo "underlight needs Rust (cargo). Install it with rustup:" >&2
    echo "  curl --proto '=https' --tlsv1.2 -sSf https://sh.rustup.rs | sh -s -- -y && . \"\$HOME/.cargo/env\"" >&2
    exit 1
  fi
fi
