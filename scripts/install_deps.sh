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
  libssl-dev                            # which certificate wrote a sample (dds/identity.cpp)
  clang-format                          # house style, checked by the Style.Format test
  clang libclang-rt-14-dev              # the sanitized build: ASan + UBSan, libFuzzer (scripts/build_sanitized.sh)
  chromium fonts-dejavu-core            # the console's browser tests (tests/browser)
)
# Node (for the browser tests' npm packages): Debian's, unless a newer one is already installed.
command -v npm >/dev/null 2>&1 || PACKAGES+=(nodejs npm)

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install_deps: all ${#PACKAGES[@]} packages present"
else
  SUDO=""
  [ "$(id -u)" -eq 0 ] || SUDO="sudo"
  echo "install_deps: installing ${#missing[@]} packages: ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
  echo "install_deps: done"
fi

# npm packages, pinned in their package-lock.json (the field has no internet: nothing is fetched
# at run time, and the console serves only its own files).
# The console's own libraries (Leaflet) are served by the base; the browser tests' (playwright-core) drive it;
# the bag tests' (@mcap/core, fzstd) read Cairn's recordings as the reference implementation does.
for dir in base_station/console/web tests/browser tests/bag; do
  npm_dir="$(dirname "$0")/../$dir"
  if ! cmp -s "$npm_dir/package-lock.json" "$npm_dir/node_modules/.installed-lock.json" 2>/dev/null; then
    npm ci --prefix "$npm_dir" --no-audit --no-fund --loglevel=error >/dev/null
    cp "$npm_dir/package-lock.json" "$npm_dir/node_modules/.installed-lock.json"
    echo "install_deps: npm packages for $dir installed"
  fi
done
