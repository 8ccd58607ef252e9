#!/usr/bin/env bash
# Installs the Debian packages listed in scripts/packages.txt (or in the list file given as the one
# argument, e.g. scripts/packages-bench.txt) that are missing. A package named NAME:ARCH (libenet-dev:arm64)
# is another architecture's build (Debian multiarch): that architecture is added to dpkg first.
# Quiet when everything is present; needs root (or sudo) only when something must be installed.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
list="${1:-$here/packages.txt}"
if [[ ! -r "$list" ]]; then
  echo "install-deps: cannot read package list '$list'" >&2; exit 2
fi
mapfile -t wanted < <(grep -v -E '^\s*(#|$)' "$list")
missing=()
native="$(dpkg --print-architecture)"
for pkg in "${wanted[@]}"; do
  # Once dpkg knows a second architecture, a plain name matches both builds of a package; a plain name in
  # a list means this machine's own (or an Architecture: all one).
  arches="$native|all"
  [[ "$pkg" == *:* ]] && arches="${pkg##*:}"
  dpkg-query -W -f='${Architecture} ${Status}\n' "$pkg" 2>/dev/null | grep -q -x -E "($arches) install ok installed" ||
    missing+=("$pkg")
done
[[ ${#missing[@]} -eq 0 ]] && exit 0
echo "install-deps: installing missing Debian packages: ${missing[*]}" >&2
sudo_cmd=()
if [[ "$(id -u)" -ne 0 ]]; then
  if command -v sudo >/dev/null 2>&1; then sudo_cmd=(sudo); else
    echo "install-deps: need root or sudo to install: ${missing[*]}" >&2; exit 1
  fi
fi
export DEBIAN_FRONTEND=noninteractive
# apt only fetches the package lists of the architectures dpkg knows, so add the foreign ones before the update.
for arch in $(printf '%s\n' "${missing[@]}" | sed -n 's/^[^:]*:\([a-z0-9]*\)$/\1/p' | sort -u); do
  if [[ "$arch" != "$native" ]] && ! dpkg --print-foreign-architectures | grep -qx "$arch"; then
    echo "install-deps: adding the $arch architecture to dpkg (multiarch)" >&2
    "${sudo_cmd[@]}" dpkg --add-architecture "$arch"
  fi
done
# Another apt run (a second checkout installing its own list) holds the dpkg lock: wait for it.
"${sudo_cmd[@]}" apt-get -o DPkg::Lock::Timeout=600 update -qq
"${sudo_cmd[@]}" apt-get -o DPkg::Lock::Timeout=600 install -y -qq --no-install-recommends "${missing[@]}"
