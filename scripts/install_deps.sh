#!/usr/bin/env bash
# Installs Cairn's build and runtime dependencies from Debian 12 packages.
# Idempotent: only packages that are not installed yet are fetched.
set -euo pipefail

PACKAGES=(
  build-essential cmake ninja-build ccache pkg-config git
  libfastrtps-dev libfastcdr-dev fastddsgen fastdds-tools
  libeigen3-dev libceres-dev libopencv-dev libpcl-dev liboctomap-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libyaml-cpp-dev nlohmann-json3-dev libcpp-httplib-dev libspdlog-dev libcli11-dev
  libsqlite3-dev libzstd-dev zlib1g-dev
  python3 procps
  iproute2 nftables                     # emulated radio link (cairn_mission --link-loss/--link-kbit)
  openssl                               # DDS Security certificates (deploy/security/make_certs.sh)
  clang-format                          # house style, checked by the Style.Format test
)

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install_deps: all ${#PACKAGES[@]} packages present"
  exit 0
fi

SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
echo "install_deps: installing ${#missing[@]} packages: ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "install_deps: done"
