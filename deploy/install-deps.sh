#!/usr/bin/env bash
# Installs Tessera's build and runtime dependencies from Debian 12 packages only.
set -euo pipefail
packages=(
  build-essential cmake pkg-config
  libembree-dev embree-tools
  libgrpc++-dev protobuf-compiler-grpc libprotobuf-dev protobuf-compiler
  libopenimageio-dev openimageio-tools
  libtbb-dev libgtest-dev libgmock-dev libbenchmark-dev libabsl-dev
  libtinyobjloader-dev libcli11-dev nlohmann-json3-dev libspdlog-dev libboost-context-dev
  libtinygltf-dev  # tessera render's glTF loader (tools/tessera/scene)
  openssl  # the security tests make their certificates with it
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi
sudo=""
if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
echo "Installing: ${missing[*]}"
$sudo apt-get update -qq
DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
