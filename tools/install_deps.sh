#!/usr/bin/env bash
# Installs what silokit needs on Debian 12 (as root): compilers, cmake, ccache,
# Open MPI, VTK (LIGGGHTS' ParaView dump styles, doc/vtk_output.md), Debian's
# liggghts (the reference binary) and liggghts-doc (its tutorials, which
# bench/stock_tutorials.py runs), Python with numpy, scipy, matplotlib,
# pytest (and pytest-xdist: tools/test.sh --fast runs on two workers) and
# VTK's bindings (the tests read the frames back with them),
# setuptools and venv (pip install -e . of pyproject.toml, offline), and a
# deb-src entry so that `apt-get source liggghts` works. Does nothing when
# everything is already there.
set -euo pipefail

packages=(build-essential cmake ccache patch xz-utils dpkg-dev
          openmpi-bin libopenmpi-dev libvtk9-dev liggghts liggghts-doc
          python3 python3-numpy python3-scipy python3-matplotlib python3-pytest python3-pytest-xdist python3-vtk9
          python3-setuptools python3-venv)

# deb-src for Debian's main archive, same mirror and suite as the existing
# `deb` entry (deb822 .sources or one-line .list format)
sources_file=/etc/apt/sources.list.d/silokit-deb-src.sources
have_deb_src() {
  grep -rqsE '^(deb-src|Types:.*deb-src)' /etc/apt/sources.list /etc/apt/sources.list.d/
}
add_deb_src() {
  local uri="" suite=""
  if [ -f /etc/apt/sources.list.d/debian.sources ]; then
    uri=$(awk '/^URIs:/{print $2; exit}' /etc/apt/sources.list.d/debian.sources)
    suite=$(awk '/^Suites:/{print $2; exit}' /etc/apt/sources.list.d/debian.sources)
  fi
  if [ -z "$uri" ] && [ -f /etc/apt/sources.list ]; then
    read -r uri suite < <(awk '$1=="deb" && $0 !~ /security/ {
        for (i = 2; i <= NF; i++) if ($i ~ /^[a-z]+:\/\//) { print $i, $(i+1); exit } }' /etc/apt/sources.list)
  fi
  uri=${uri:-http://deb.debian.org/debian}
  suite=${suite:-bookworm}
  echo "silokit: adding deb-src $uri $suite main ($sources_file)"
  cat > "$sources_file" <<SRC
Types: deb-src
URIs: $uri
Suites: $suite
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg
SRC
}

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

need_update=0
if ! have_deb_src; then add_deb_src; need_update=1; fi
[ ${#missing[@]} -gt 0 ] && need_update=1

if [ $need_update -eq 1 ]; then
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -q
  if [ ${#missing[@]} -gt 0 ]; then
    echo "silokit: installing ${missing[*]}"
    apt-get install -y -q --no-install-recommends "${missing[@]}"
  fi
fi
