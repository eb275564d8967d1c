#!/usr/bin/env bash
# Builds the throng-server image without any registry: a bookworm base made with debootstrap
# (--variant=minbase) and imported into podman, then deploy/docker/Containerfile on top.
# Needs root, podman, runc and debootstrap (Debian packages; install-deps does not install them,
# this script does). Podman runs with --runtime runc --cgroup-manager=cgroupfs, which is what
# works on these machines.
#   deploy/docker/build-image.sh [TAG=throng-server:latest]
set -euo pipefail
tag=${1:-throng-server:latest}
here=$(cd "$(dirname "$0")/../.." && pwd)
[[ $(id -u) -eq 0 ]] || { echo "build-image: needs root (debootstrap, podman)" >&2; exit 2; }
missing=()
for p in podman runc debootstrap; do command -v "$p" >/dev/null || missing+=("$p"); done
if ((${#missing[@]})); then
  echo "build-image: installing ${missing[*]}"
  apt-get update && DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends podman runc debootstrap
fi
conf=/etc/containers/containers.conf
if ! grep -q '^default_ulimits *= *\[\]' "$conf" 2>/dev/null; then
  mkdir -p /etc/containers
  printf '[containers]\ndefault_ulimits = []\n' >>"$conf"
fi
pm() { podman --runtime runc --cgroup-manager=cgroupfs "$@"; }

if ! pm image exists localhost/throng-base:bookworm; then
  root=$(mktemp -d /tmp/throng-rootfs.XXXXXX)
  echo "build-image: debootstrap --variant=minbase bookworm into $root"
  debootstrap --variant=minbase bookworm "$root" http://deb.debian.org/debian >/tmp/throng-debootstrap.log
  tar -C "$root" -c . | pm import - localhost/throng-base:bookworm
  rm -rf "$root"
fi
echo "build-image: building $tag"
# docker format: OCI images drop HEALTHCHECK.
pm build --format docker --network host -f "$here/deploy/docker/Containerfile" -t "$tag" "$here"
pm image ls "$tag"
