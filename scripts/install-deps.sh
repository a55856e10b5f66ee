#!/usr/bin/env bash
# install-deps.sh: installs every Debian 12 package ltm needs. Idempotent and non-interactive:
# it only calls apt-get when something is missing. Works as root or through sudo.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config
  libembree-dev libtbb-dev
  libnanoflann-dev libtinyobjloader-dev nlohmann-json3-dev libcli11-dev
  libspdlog-dev libfmt-dev libstb-dev libopenexr-dev zlib1g-dev libtinygltf-dev
  assimp-utils
  libgtest-dev libgmock-dev libbenchmark-dev
  chromium   # the viewer's test in a real browser (tests/web/viewer_test.sh; it skips without it)
)
# libtorch is needed only for the model layers (LTM_WITH_TORCH=ON, the default).
if [[ "${LTM_WITH_TORCH:-ON}" != "OFF" ]]; then
  packages+=(libtorch-dev libopenblas0-pthread libgloo-dev)   # gloo: c10d data-parallel training
fi

missing=()
for p in "${packages[@]}"; do
  status=$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)
  [[ "$status" == "install ok installed" ]] || missing+=("$p")
done

if [[ ${#missing[@]} -eq 0 ]]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

echo "install-deps: installing ${missing[*]}"
sudo_cmd=()
if [[ $(id -u) -ne 0 ]]; then sudo_cmd=(sudo); fi
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -q
"${sudo_cmd[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}"
