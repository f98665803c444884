#!/usr/bin/env bash
# The fast first run (issue 33, D64) on a really fresh Debian 12: debootstrap a minimal bookworm into a
# scratch folder, clone this repository into it and time `scripts/demo` inside a chroot from the start to
# its first video — the package installation (`setup-deps --run`, from the mirror), the configure, the
# build of the CLI and the default face, the first render. This is how the missing run packages
# (openimageio-tools, libblas-dev, liblapack-dev) and the pybind11 configure failure were found: a
# machine that has the test packages never shows them. Needs root, debootstrap (installed if missing) and
# the Debian mirror; takes ~10 minutes and ~3 GB in /tmp (removed after).
#   usage: bench/first_run.sh [MIRROR]   (default http://deb.debian.org/debian)
#   FIRST_RUN_LOG  where the demo's timed output is kept (default /tmp/first_run-demo.log)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
mirror="${1:-http://deb.debian.org/debian}"
log="${FIRST_RUN_LOG:-${TMPDIR:-/tmp}/first_run-demo.log}"  # kept after the chroot is removed
((EUID == 0)) || { echo "first_run: needs root (debootstrap, chroot)"; exit 1; }
command -v debootstrap >/dev/null || DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends debootstrap >/dev/null
T=$(mktemp -d /tmp/talkhead-first-run.XXXXXX)
cleanup() {
	# End what still runs in the chroot (the demo goes on after its first video), unmount, and never remove
	# across a mount: once a busy bind-mounted /dev stayed mounted and `rm -rf` took the host's device nodes.
	local p
	for p in /proc/[0-9]*; do
		case "$(readlink "$p/root" 2>/dev/null)" in "$T/root" | "$T/root/"*) kill -9 "${p#/proc/}" 2>/dev/null || true ;; esac
	done
	sleep 1
	for m in proc sys dev; do umount "$T/root/$m" 2>/dev/null || umount -l "$T/root/$m" 2>/dev/null || true; done
	if grep -q " $T/" /proc/mounts; then
		echo "first_run: $T still has mounts; left in place" >&2
		return
	fi
	rm -rf --one-file-system "$T"
}
trap cleanup EXIT
echo "first_run: debootstrap bookworm (not timed)"
debootstrap --variant=minbase bookworm "$T/root" "$mirror" >"$T/debootstrap.log" 2>&1 || { tail "$T/debootstrap.log"; exit 1; }
for m in proc sys dev; do mount --bind "/$m" "$T/root/$m"; done
cp /etc/resolv.conf "$T/root/etc/"
git clone -q "$root" "$T/root/root/talkhead"
echo "first_run: scripts/demo in the chroot ($(nproc) cores)"
start=$EPOCHSECONDS
chroot "$T/root" /usr/bin/env -i HOME=/root PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin LANG=C.UTF-8 \
	/bin/bash -c 'cd /root/talkhead && scripts/demo' 2>&1 | while IFS= read -r line; do
	at=$((EPOCHSECONDS - start))  # seconds from the start (bash's clock: no process per line)
	printf '%s %s\n' "$at" "$line" >>"$T/demo.log"
	case "$line" in
		"setup-deps: "*) echo "$line" ;;
		"Fetched "*) echo "first_run: downloaded after $at s: $line" ;;
		"Unpacking "*) [[ -n "${unpacking:-}" ]] || { unpacking=1; echo "first_run: unpacking from $at s"; } ;;
		"["*"] Linking CXX executable talkhead") echo "first_run: the CLI linked after $at s" ;;
		*"Build files have been written"*) echo "first_run: packages installed, configured after $at s" ;;
		"demo: the first video"*) echo "first_run: $line (from the clone: $at s)"; break ;;
	esac
done || true  # the demo goes on after its first video; leaving the loop stops it (SIGPIPE)
cp "$T/demo.log" "$log"
echo "first_run: the demo's output, each line with its second, is in $log"
grep -q "demo: the first video" "$T/demo.log" || { echo "first_run: no first video"; tail -20 "$T/demo.log"; exit 1; }
