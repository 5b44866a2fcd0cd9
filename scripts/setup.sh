#!/usr/bin/env bash
# Installs what sward needs on Debian/Ubuntu when it is missing: a C++ compiler (glslang is built
# from source), the Vulkan loader, Mesa's lavapipe (a Vulkan driver that runs on the CPU; on
# Debian 12 Mesa 25, from bookworm-backports), the
# Khronos validation layer, EGL and Mesa's GL drivers (wgpu's GL backend on the CPU) and, with
# --xvfb (the tests' set-up), a virtual X server for windowed tests and node and Chromium for the
# portable renderer's test in a browser's WebGPU, and the headers a new Bevy game builds with.
# Then installs rustup where there is none, and
# the toolchain rust-toolchain.toml pins with its components and the browser's target (rustup
# itself installs nothing on first use where RUSTUP_AUTO_INSTALL=0). Safe to run again: it
# installs nothing that is already there.
set -euo pipefail

want_xvfb=0
[[ "${1:-}" == "--xvfb" ]] && want_xvfb=1

as_root() {
  if [[ $(id -u) -eq 0 ]]; then "$@"; else sudo "$@"; fi
}

missing=()
have_pkg() { dpkg-query -W -f='${Status}' "$1" 2>/dev/null | grep -q "install ok installed"; }
# GL through EGL (Mesa's llvmpipe, no display) for the portable renderer's tests on wgpu's GL
# backend.
for pkg in libvulkan1 mesa-vulkan-drivers vulkan-validationlayers g++ pkg-config \
  libegl1 libegl-mesa0 libgles2 libgl1-mesa-dri; do
  have_pkg "$pkg" || missing+=("$pkg")
done
if [[ $want_xvfb -eq 1 ]]; then
  have_pkg xvfb || missing+=(xvfb)
  have_pkg xauth || missing+=(xauth)
  # A new Bevy game's build, with Bevy's default features (the quick start's test): ALSA,
  # udev, X11, xkbcommon and Wayland's headers.
  for pkg in libasound2-dev libudev-dev libx11-dev libxkbcommon-dev libwayland-dev; do
    have_pkg "$pkg" || missing+=("$pkg")
  done
  # The portable WGSL run in headless Chromium's WebGPU (SwiftShader, no GPU), driven by node.
  command -v node >/dev/null || missing+=(nodejs)
  if ! command -v chromium >/dev/null && ! command -v chromium-browser >/dev/null; then
    # Debian names it chromium; Ubuntu's apt has only chromium-browser.
    if apt-cache show chromium >/dev/null 2>&1; then missing+=(chromium); else missing+=(chromium-browser); fi
  fi
fi

# Debian 12's lavapipe (Mesa 22.3) aborts inside its own threads on some of Bevy 0.20's
# pipelines; bookworm-backports' Mesa 25 draws them, and adds mesh shaders (the mesh route is
# tested on it). Mesa (its Vulkan and GL drivers, one version for both, as the tests compare
# them) and the libdrm it needs come from backports: an apt pin holds every other package to
# bookworm.
backports_pin=/etc/apt/preferences.d/sward-lavapipe
needs_update=0
if [[ "$(. /etc/os-release 2>/dev/null && echo "${VERSION_CODENAME:-}")" == bookworm ]]; then
  if [[ ! -f $backports_pin ]]; then
    echo "sward setup: taking Mesa 25 (lavapipe, llvmpipe) from bookworm-backports"
    if ! grep -rqs bookworm-backports /etc/apt/sources.list /etc/apt/sources.list.d/; then
      printf '%s\n' "Types: deb" "URIs: http://deb.debian.org/debian" "Suites: bookworm-backports" \
        "Components: main" "Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg" |
        as_root tee /etc/apt/sources.list.d/sward-bookworm-backports.sources >/dev/null
    fi
    printf '%s\n' "Package: src:mesa src:libdrm" "Pin: release n=bookworm-backports" \
      "Pin-Priority: 990" | as_root tee $backports_pin >/dev/null
    needs_update=1
  fi
  for pkg in mesa-vulkan-drivers libgl1-mesa-dri libegl-mesa0; do
    installed=$(dpkg-query -W -f='${Version}' "$pkg" 2>/dev/null || true)
    if [[ -n $installed ]] && dpkg --compare-versions "$installed" lt 25; then
      missing+=("$pkg")
    fi
  done
fi

if [[ ${#missing[@]} -gt 0 || $needs_update -eq 1 ]]; then
  if ! command -v apt-get >/dev/null; then
    echo "sward setup: please install ${missing[*]} (no apt-get on this machine)" >&2
    exit 1
  fi
  as_root apt-get update -qq
  if [[ ${#missing[@]} -gt 0 ]]; then
    echo "sward setup: installing ${missing[*]}"
    DEBIAN_FRONTEND=noninteractive as_root apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
  fi
fi

if ! command -v cargo >/dev/null; then
  [[ -f "$HOME/.cargo/env" ]] && source "$HOME/.cargo/env"
fi
if ! command -v cargo >/dev/null; then
  echo "sward setup: installing the Rust toolchain with rustup"
  have_pkg curl || { as_root apt-get update -qq; as_root apt-get install -y -qq curl ca-certificates >/dev/null; }
  curl --proto '=https' --tlsv1.2 -sSf https://sh.rustup.rs | sh -s -- -y --profile minimal --default-toolchain none
  source "$HOME/.cargo/env"
fi

# The one toolchain sward builds with (rust-toolchain.toml), its components and targets.
sward_toolchain=$(sed -n 's/^channel = "\(.*\)"/\1/p' "$(dirname "${BASH_SOURCE[0]}")/../rust-toolchain.toml")
if ! rustup run "$sward_toolchain" rustc --print target-list >/dev/null 2>&1 ||
  ! rustup target list --installed --toolchain "$sward_toolchain" 2>/dev/null | grep -q '^wasm32-unknown-unknown$' ||
  ! rustup component list --installed --toolchain "$sward_toolchain" 2>/dev/null | grep -q '^clippy'; then
  echo "sward setup: installing Rust $sward_toolchain with rustfmt, clippy and the wasm32-unknown-unknown target"
  rustup toolchain install "$sward_toolchain" --profile minimal -c rustfmt,clippy -t wasm32-unknown-unknown
fi
