#!/usr/bin/env bash
# Installs Tessera's dependencies from Debian 12 packages only.
#   deploy/install-deps.sh             what building and testing Tessera needs (the default)
#   deploy/install-deps.sh --build     what building it needs, without the test tools
#                                      (deploy/container/Containerfile's build stage)
#   deploy/install-deps.sh --runtime   what the installed programs need to run, nothing else
#                                      (deploy/container/Containerfile's final stage)
#   deploy/install-deps.sh --print-runtime
#                                      print the runtime list, one package a line, install nothing
#                                      (tests/deploy checks it against the built binaries)
set -euo pipefail
build_packages=(
  build-essential cmake pkg-config
  libembree-dev embree-tools
  libgrpc++-dev protobuf-compiler-grpc libprotobuf-dev protobuf-compiler
  libopenimageio-dev openimageio-tools
  libtbb-dev libgtest-dev libgmock-dev libbenchmark-dev libabsl-dev
  libtinyobjloader-dev libcli11-dev nlohmann-json3-dev libspdlog-dev libboost-context-dev
  libtinygltf-dev  # tessera render's glTF loader (tools/tessera/scene)
  libxxhash-dev  # XXH64 (api/src/hash.cc)
)
test_packages=(
  openssl  # the security tests make their certificates with it
  # tests/deploy: a one-machine Slurm cluster runs deploy/slurm (installing slurmd and slurmctld
  # enables their services, which do not start without an /etc/slurm/slurm.conf); the linters
  # check deploy/.
  slurmctld slurmd slurm-client munge
  shellcheck yamllint python3 python3-yaml
  systemd  # systemd-analyze verify checks deploy/systemd's units
)
# The libraries the installed programs (tessera-worker, tessera, libtessera, libtessera_image) are
# linked against; apt brings what these depend on. libc6, libgcc-s1 and libstdc++6 come with any
# Debian. tests/deploy/runtime_packages_test.sh fails when a built binary needs a library from a
# package missing here.
runtime_packages=(
  libembree3-3 libtbb12
  libgrpc++1.51 libgrpc29 libprotobuf32 libabsl20220623 libssl3
  libopenimageio2.4
  libspdlog1.10 libfmt9
  libtinygltf2d libtinyobjloader2rc10  # tessera render's scene loaders
  libstdc++6
)
case "${1:-}" in
  "") packages=("${build_packages[@]}" "${test_packages[@]}") ;;
  --build) packages=("${build_packages[@]}") ;;
  --runtime) packages=("${runtime_packages[@]}") ;;
  --print-runtime)
    printf '%s\n' "${runtime_packages[@]}"
    exit 0
    ;;
  *)
    echo "usage: $0 [--build | --runtime | --print-runtime]" >&2
    exit 2
    ;;
esac
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
