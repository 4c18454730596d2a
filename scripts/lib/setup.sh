# Sourced by the scripts: installs what symdyn needs from Debian's packages.
#   symdyn_require_packages <package>...
# Installs the missing packages when run as root (apt-get update first); otherwise
# prints the exact apt-get line to run and exits non-zero.

symdyn_base_packages=(g++ cmake ninja-build pkg-config libeigen3-dev libfmt-dev catch2 libcli11-dev
  nlohmann-json3-dev libbenchmark-dev librapidcheck-dev libsundials-dev libtinygltf-dev
  python3-dev python3-numpy pybind11-dev ccache python3-jsonschema liburdfdom-dev
  python3-distributed python3-h5py libhdf5-dev help2man dpkg-dev man-db libassimp-dev)

symdyn_require_packages() {
  local missing=()
  local pkg
  for pkg in "$@"; do
    dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q "install ok installed" || missing+=("$pkg")
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  if ! command -v apt-get >/dev/null 2>&1; then
    echo "error: missing packages (${missing[*]}) and no apt-get: symdyn expects Debian 12." >&2
    exit 1
  fi
  if [ "$(id -u)" -ne 0 ]; then
    echo "error: missing Debian packages: ${missing[*]}" >&2
    echo "Install them as root, then run this script again:" >&2
    echo "  apt-get update && apt-get install -y ${missing[*]}" >&2
    exit 1
  fi
  echo "symdyn: installing ${missing[*]}"
  apt-get update -qq || { echo "error: apt-get update failed" >&2; exit 1; }
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${missing[@]}" >/dev/null ||
    { echo "error: apt-get install ${missing[*]} failed" >&2; exit 1; }
}

# symdyn_require_command <command> <package>: installs the package only when the
# command is missing (npm may come with a Node.js that is not Debian's).
symdyn_require_command() {
  command -v "$1" >/dev/null 2>&1 || symdyn_require_packages "$2"
}
