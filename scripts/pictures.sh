#!/usr/bin/env bash
# Makes every picture in README.md and docs/ again, each with the command its caption names.
#
#   scripts/pictures.sh                the pictures made on lavapipe (Mesa's CPU Vulkan driver;
#                                      about 8 minutes on 2 cores, after the build)
#   scripts/pictures.sh --gpu          the pictures made on a GPU (the H100's in the README): the
#                                      prairie does not fit lavapipe, and Bevy's need a GPU's speed
#   scripts/pictures.sh NAME...        only docs/NAME.png, wherever it is made
#   scripts/pictures.sh --list [NAME]  each picture, where it is made and its commands, as
#                                      NAME<tab>WHERE<tab>COMMAND lines (nothing is built)
#
# It sets up and builds as scripts/run.sh does (release builds of sward, the montage example
# and, for Bevy's pictures, sward-bevy's examples). With SWARD_BIN=DIR it uses the binaries
# `sward`, `montage` and sward-bevy's examples in DIR instead and builds nothing: for a GPU machine
# the binaries were copied to. The pictures are drawn on the device sward picks (`--gpu` is
# sward's flag for another).
set -euo pipefail
cd "$(dirname "$0")/.."

# Every picture: its name (docs/NAME.png), where it is made, then its commands. A picture of one
# command names that command in its caption; one of several (crops joined by the montage
# example) names `scripts/pictures.sh NAME`. $PARTS is a scratch folder for the pieces.
pictures() {
  picture prairie gpu \
    "sward render --scene prairie --width 960 --height 540 --out docs/prairie.png"
  picture trample-animated lavapipe \
    "sward render --scene trample --width 320 --height 180 --steps 120 --animation 36 --fps 12 --out docs/trample-animated.png"
  picture trail-animated lavapipe \
    "sward render --scene trail --width 320 --height 180 --steps 600 --animation 48 --fps 12 --out docs/trail-animated.png"
  picture trail lavapipe \
    "sward render --scene trail --width 1280 --height 720 --steps 1200 --out docs/trail.png"
  picture meadow lavapipe \
    "sward render --scene meadow --width 960 --height 540 --out docs/meadow.png"
  picture closeup-shading lavapipe \
    "sward render --scene meadow --width 1920 --height 1080 --out \$PARTS/meadow.png" \
    "montage --row --out docs/closeup-shading.png \$PARTS/meadow.png@480,840,960,240"
  picture planet lavapipe \
    "sward render --scene planet --width 960 --height 540 --out docs/planet.png"
  picture hills lavapipe \
    "sward render --scene hills --width 960 --height 540 --out docs/hills.png"
  picture trample lavapipe \
    "sward render --scene trample --width 960 --height 540 --out docs/trample.png"
  picture both lavapipe \
    "sward render --technique both --set instanced.inner_radius=12 --width 1280 --height 720 --out docs/both.png"
  picture instanced lavapipe \
    "sward render --technique instanced --width 1280 --height 720 --out docs/instanced.png"
  picture landscape lavapipe \
    "sward render --scene landscape --width 1280 --height 720 --out docs/landscape.png"
  picture billboard lavapipe \
    "sward render --technique billboard --width 1280 --height 720 --out docs/billboard.png"
  picture closeup-billboards lavapipe \
    "sward render --technique instanced --width 1920 --height 1080 --out \$PARTS/instanced.png" \
    "sward render --technique billboard --width 1920 --height 1080 --out \$PARTS/billboard.png" \
    "montage --row --out docs/closeup-billboards.png \$PARTS/instanced.png@640,700,640,380 \$PARTS/billboard.png@640,700,640,380"
  picture blade-shadows lavapipe \
    "sward render --scene meadow --quality ultra --set field.blades=12000 --set 'shading.light_direction=[0.8,0.3,0.3]' --set shading.blade_shadows=off --width 960 --height 540 --out \$PARTS/without.png" \
    "sward render --scene meadow --quality ultra --set field.blades=12000 --set 'shading.light_direction=[0.8,0.3,0.3]' --set shading.blade_shadows=on --width 960 --height 540 --out \$PARTS/with.png" \
    "montage --column --out docs/blade-shadows.png \$PARTS/without.png@0,230,960,310 \$PARTS/with.png@0,230,960,310"
  picture viewer lavapipe \
    "sward view --scene meadow --width 1280 --height 720 --frames 20 --screenshot docs/viewer.png"
  picture openworld lavapipe \
    "sward render --scene openworld --width 1280 --height 720 --steps 120 --out docs/openworld.png"
  picture openworld-animated gpu \
    "sward render --scene openworld --set camera_path.speed=60 --width 320 --height 180 --steps 60 --animation 120 --fps 12 --out docs/openworld-animated.png"
  picture park gpu \
    "sward render --scene park --width 1920 --height 1080 --out docs/park.png"
  picture park-lavapipe lavapipe \
    "sward render --scene park --width 1920 --height 1080 --out docs/park-lavapipe.png"
  picture park-flowering lavapipe \
    "sward render --scene park --width 1920 --height 1080 --set 'camera_path.points=[[20.0,1.2,-40.0],[40.0,1.2,-20.0]]' --set camera_path.speed=0.01 --out docs/park-flowering.png"
  picture presets lavapipe \
    "sward render --scene crates/sward-bevy/src/presets/lawn.grass.toml --width 480 --height 270 --out \$PARTS/lawn.png" \
    "sward render --scene crates/sward-bevy/src/presets/meadow.grass.toml --width 480 --height 270 --out \$PARTS/meadow.png" \
    "sward render --scene crates/sward-bevy/src/presets/wildflower-meadow.grass.toml --width 480 --height 270 --out \$PARTS/wildflower-meadow.png" \
    "sward render --scene crates/sward-bevy/src/presets/prairie.grass.toml --width 480 --height 270 --out \$PARTS/prairie.png" \
    "sward render --scene crates/sward-bevy/src/presets/pampas.grass.toml --width 480 --height 270 --out \$PARTS/pampas.png" \
    "sward render --scene crates/sward-bevy/src/presets/reed-marsh.grass.toml --width 480 --height 270 --out \$PARTS/reed-marsh.png" \
    "sward render --scene crates/sward-bevy/src/presets/dune-grass.grass.toml --width 480 --height 270 --out \$PARTS/dune-grass.png" \
    "sward render --scene crates/sward-bevy/src/presets/savanna.grass.toml --width 480 --height 270 --out \$PARTS/savanna.png" \
    "sward render --scene crates/sward-bevy/src/presets/alpine.grass.toml --width 480 --height 270 --out \$PARTS/alpine.png" \
    "sward render --scene crates/sward-bevy/src/presets/forest-floor.grass.toml --width 480 --height 270 --out \$PARTS/forest-floor.png" \
    "sward render --scene crates/sward-bevy/src/presets/frosted-meadow.grass.toml --width 480 --height 270 --out \$PARTS/frosted-meadow.png" \
    "sward render --scene crates/sward-bevy/src/presets/stylised.grass.toml --width 480 --height 270 --out \$PARTS/stylised.png" \
    "montage --row --out \$PARTS/row0.png \$PARTS/lawn.png \$PARTS/meadow.png \$PARTS/wildflower-meadow.png \$PARTS/prairie.png" \
    "montage --row --out \$PARTS/row1.png \$PARTS/pampas.png \$PARTS/reed-marsh.png \$PARTS/dune-grass.png \$PARTS/savanna.png" \
    "montage --row --out \$PARTS/row2.png \$PARTS/alpine.png \$PARTS/forest-floor.png \$PARTS/frosted-meadow.png \$PARTS/stylised.png" \
    "montage --column --out docs/presets.png \$PARTS/row0.png \$PARTS/row1.png \$PARTS/row2.png"
  picture bevy-pbr gpu \
    "ball --bench 600 --pbr --out docs/bevy-pbr.png"
  picture bevy-garden gpu \
    "garden --shot docs/bevy-garden.png --frames 300"
  picture bevy-openworld gpu \
    "openworld --shot docs/bevy-openworld.png --frames 600 --speed 100"
  picture bevy-gallery gpu \
    "gallery --shot docs/bevy-gallery.png --frames 300"
  picture bevy-paint gpu \
    "paint --shot docs/bevy-paint.png --frames 300"
  picture bevy-footsteps gpu \
    "footsteps --shot docs/bevy-footsteps.png --frames 300"
  picture bevy-topdown lavapipe \
    "topdown --shot docs/bevy-topdown.png --frames 60"
  # The web example's page in headless Chromium (SwiftShader's WebGPU, no GPU needed): its test's
  # picture.
  picture bevy-web lavapipe \
    "cargo test --locked -p sward-bevy --test web" \
    "cp \${CARGO_TARGET_DIR:-target}/tmp/web-example/web-example.png docs/bevy-web.png"
  picture bevy-assets gpu \
    "assets --shot docs/bevy-assets.png --frames 300"
  picture wildflower-meadow gpu \
    "sward render --scene crates/sward-bevy/src/presets/wildflower-meadow.grass.toml --width 1920 --height 1080 --out docs/wildflower-meadow.png"
  picture reed-marsh lavapipe \
    "sward render --scene crates/sward-bevy/src/presets/reed-marsh.grass.toml --width 1920 --height 1080 --out \$PARTS/camera.png" \
    "sward render --scene crates/sward-bevy/src/presets/reed-marsh.grass.toml --set 'camera.position=[0.0, 1.7, -6.0]' --set 'camera.target=[0.0, 1.2, 8.0]' --width 1920 --height 1080 --out \$PARTS/walker.png" \
    "montage --column --out docs/reed-marsh.png \$PARTS/camera.png \$PARTS/walker.png"
  picture bevy-character gpu \
    "character --shot docs/bevy-character.png --frames 300"
  picture bevy-garden-crops gpu \
    "garden --shot \$PARTS/forward.png --frames 300" \
    "garden --shot \$PARTS/deferred.png --frames 300 --deferred" \
    "garden --shot \$PARTS/plain.png --frames 300 --no-taa --no-ssao" \
    "montage --row --gap 0 --out docs/bevy-garden-crops.png \$PARTS/forward.png@200,680,640,360 \$PARTS/deferred.png@200,680,640,360 \$PARTS/plain.png@200,680,640,360"
}

# How a command's program is spelled in a caption: sward's examples run through cargo.
spelled() {
  case "$1" in
    sward) echo "sward" ;;
    montage) echo "cargo run --release -p sward --example montage --" ;;
    ball | garden | openworld | gallery | paint | footsteps | topdown | assets) echo "cargo run --release -p sward-bevy --example $1 --" ;;
    character) echo "cargo run --release -p sward-bevy --features avian --example $1 --" ;;
    cargo | cp) echo "$1" ;;
  esac
}

action=make
wanted=()
where_wanted=
for arg in "$@"; do
  case "$arg" in
    --list) action=list ;;
    --gpu) where_wanted=gpu ;;
    -h | --help) sed -n '2,16p' "$0" | cut -c3-; exit 0 ;;
    -*) echo "pictures: unknown flag $arg; the flags are --list and --gpu, the rest names pictures" >&2; exit 2 ;;
    *) wanted+=("${arg%.png}") ;;
  esac
done
# --list alone lists every picture; a run alone makes lavapipe's.
if [[ -z $where_wanted ]]; then
  if [[ $action == list ]]; then where_wanted=all; else where_wanted=lavapipe; fi
fi

# Whether the picture NAME made WHERE is one this run makes.
chosen() {
  if [[ ${#wanted[@]} -gt 0 ]]; then
    [[ " ${wanted[*]} " == *" $1 "* ]]
  else
    [[ $where_wanted == all || $2 == "$where_wanted" ]]
  fi
}

list_picture() {
  local name=$1 where=$2 command
  shift 2
  for command in "$@"; do
    printf '%s\t%s\t%s %s\n' "$name" "$where" "$(spelled "${command%% *}")" "${command#* }"
  done
}

made=()
make_picture() {
  local name=$1 where=$2 command started
  shift 2
  echo "pictures: docs/$name.png ($where)"
  started=$SECONDS
  for command in "$@"; do
    echo "  $command"
    eval "$command"
  done
  made+=("docs/$name.png ($((SECONDS - started)) s)")
}

picture() {
  chosen "$1" "$2" || return 0
  if [[ $action == list ]]; then list_picture "$@"; else make_picture "$@"; fi
}

if [[ $action == list ]]; then
  pictures
  exit 0
fi

known=$(action=list; wanted=(); where_wanted=all; pictures | cut -f1 | sort -u)
for name in "${wanted[@]}"; do
  grep -qx "$name" <<<"$known" || {
    echo "pictures: there is no picture $name; the pictures are: $(echo $known)" >&2
    exit 2
  }
done

# The programs the commands name.
if [[ -n ${SWARD_BIN:-} ]]; then
  bin=$(cd "$SWARD_BIN" && pwd)
else
  source scripts/setup.sh --xvfb
  [[ -f "$HOME/.cargo/env" ]] && source "$HOME/.cargo/env"
  cargo build --release --locked -p sward --bin sward --example montage
  # (grep reads all its input: with -q an early exit could fail the pipe under pipefail.)
  if (action=list; pictures) | cut -f3 | grep -- '-p sward-bevy' >/dev/null; then
    cargo build --release --locked -p sward-bevy --example ball --example garden --example openworld \
      --example gallery --example paint --example footsteps --example topdown --example assets
    cargo build --release --locked -p sward-bevy --features avian --example character
  fi
  bin=$PWD/target/release
fi
example() { if [[ -x $bin/$1 ]]; then echo "$bin/$1"; else echo "$bin/examples/$1"; fi; }
sward() {
  # The viewer needs a display; without one it gets a virtual one.
  if [[ $1 == view && -z ${DISPLAY:-}${WAYLAND_DISPLAY:-} ]]; then
    xvfb-run -a -s "-screen 0 1920x1080x24" "$bin/sward" "$@"
  else
    "$bin/sward" "$@"
  fi
}
montage() { "$(example montage)" "$@"; }
ball() { "$(example ball)" "$@"; }
garden() { "$(example garden)" "$@"; }
openworld() { "$(example openworld)" "$@"; }
gallery() { "$(example gallery)" "$@"; }
paint() { "$(example paint)" "$@"; }
footsteps() { "$(example footsteps)" "$@"; }
topdown() { "$(example topdown)" "$@"; }
# Its asset folder is the crate's (`crates/sward-bevy/assets`), wherever the binary is.
assets() { BEVY_ASSET_ROOT=$PWD/crates/sward-bevy "$(example assets)" "$@"; }
character() { "$(example character)" "$@"; }

PARTS=$(mktemp -d)
trap 'rm -rf "$PARTS"' EXIT
pictures
echo "pictures: made ${made[*]}"
if [[ ${#wanted[@]} -eq 0 && $where_wanted == lavapipe ]]; then
  echo "pictures: the GPU's pictures are made on a GPU, with scripts/pictures.sh --gpu:"
  (action=list; where_wanted=gpu; pictures) | cut -f1 | sort -u | sed 's/^/  docs\//; s/$/.png/'
fi
