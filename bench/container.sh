#!/usr/bin/env bash
# The Containerfile (examples/container, D64) built and run for real, with podman from Debian: no registry is
# reachable here, so the two base images it names (debian:12, debian:12-slim) are made locally from a
# debootstrapped minimal bookworm (`podman import`; the registry's images are the same Debian release). Then
# `podman build` (both stages: the package built from this commit, installed into the runtime image), and in
# a container: `talkhead --version`, a render of the default example (the default face made on first use
# into the cache volume), its MP4 checked with ffprobe, and `talkhead serve` answering /health. Prints the
# time of each step and the image's size. Needs root and the Debian mirror; ~10 minutes, ~4 GB.
#   usage: bench/container.sh [MIRROR]   (default http://deb.debian.org/debian)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
mirror="${1:-http://deb.debian.org/debian}"
((EUID == 0)) || { echo "container: needs root (debootstrap, podman)"; exit 1; }
need=()
for p in podman runc debootstrap ffmpeg curl; do command -v "$p" >/dev/null || need+=("$p"); done
if ((${#need[@]})); then
	echo "container: installing ${need[*]}"
	DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends "${need[@]}" fuse-overlayfs uidmap >/dev/null
fi
T=$(mktemp -d /tmp/talkhead-container.XXXXXX)
cid=""
cleanup() {
	[ -n "$cid" ] && podman rm -f "$cid" >/dev/null 2>&1 || true
	podman volume rm -f talkhead-bench-cache >/dev/null 2>&1 || true
	rm -rf --one-file-system "$T"
}
trap cleanup EXIT
step() { printf 'container: %-58s %4d s\n' "$1" "$(($(date +%s) - $2))"; }

t=$(date +%s)
if ! podman image exists localhost/debian:12 || ! podman image exists localhost/debian:12-slim; then
	debootstrap --variant=minbase bookworm "$T/rootfs" "$mirror" >"$T/debootstrap.log" 2>&1 || { tail "$T/debootstrap.log"; exit 1; }
	printf 'Types: deb\nURIs: %s\nSuites: bookworm bookworm-updates\nComponents: main\nSigned-By: /usr/share/keyrings/debian-archive-keyring.gpg\n' "$mirror" \
		>"$T/rootfs/etc/apt/sources.list.d/debian.sources"
	rm -f "$T/rootfs/etc/apt/sources.list"
	tar -C "$T/rootfs" -c . | podman import - localhost/debian:12 >/dev/null
	podman tag localhost/debian:12 localhost/debian:12-slim
	rm -rf --one-file-system "$T/rootfs"
fi
step "base images (debootstrap + podman import)" "$t"

# The build context: a clean checkout of HEAD (no build folders, outputs or research data).
git -C "$root" archive --format=tar HEAD | (mkdir -p "$T/src" && tar -C "$T/src" -x)
t=$(date +%s)
podman build --pull=never --isolation chroot --network host -f examples/container/Containerfile -t localhost/talkhead-bench "$T/src" >"$T/build.log" 2>&1 ||
	{ tail -30 "$T/build.log"; echo "container: podman build failed"; exit 1; }
step "podman build (package from source, runtime image)" "$t"
echo "container: image size $(podman image inspect localhost/talkhead-bench --format '{{.Size}}' | awk '{printf "%.0f MB", $1 / 1e6}')"

# This VM's cgroups are hybrid (v1 controllers + an empty v2), which crun refuses: runc, and the VM's own
# limits (podman's default ulimits are above them, and a container may not raise a limit).
opts=(--runtime runc --network host --ulimit "nofile=$(ulimit -n):$(ulimit -n)" --ulimit nproc=4096:4096)
run() { podman run --rm "${opts[@]}" -v "$T/work:/work" -v talkhead-bench-cache:/root/.cache/talkhead localhost/talkhead-bench "$@"; }
mkdir -p "$T/work"
cp "$root/examples/que_noticia.TextGrid" "$T/work/"
version=$(run --version)
echo "container: talkhead --version: $version"
t=$(date +%s)
run render -q --transcript /work/que_noticia.TextGrid --emotion joy -o /work/first.mp4
step "first render (default face made on first use)" "$t"
t=$(date +%s)
run render -q --transcript /work/que_noticia.TextGrid --emotion anger -o /work/second.mp4
step "second render (the face from the volume)" "$t"
for f in first second; do
	codec=$(ffprobe -v error -select_streams v:0 -show_entries stream=codec_name -of csv=p=0 "$T/work/$f.mp4")
	[ "$codec" = h264 ] || { echo "container: $f.mp4 is not H.264 video ($codec)"; exit 1; }
done
echo "container: both MP4s are H.264 ($(stat -c %s "$T/work/first.mp4") and $(stat -c %s "$T/work/second.mp4") bytes)"

port=$((20000 + RANDOM % 20000))
cid=$(podman run -d "${opts[@]}" -v talkhead-bench-cache:/root/.cache/talkhead localhost/talkhead-bench serve --listen "127.0.0.1:$port" --size 320x180)
health=""
for _ in $(seq 100); do
	health=$(curl -s --max-time 2 "http://127.0.0.1:$port/health" || true)
	[ -n "$health" ] && break
	sleep 0.2
done
[ -n "$health" ] || { podman logs "$cid" | tail; echo "container: serve did not answer /health"; exit 1; }
echo "container: serve answered /health: $health"
podman stop -t 10 "$cid" >/dev/null
echo "container: ok"
