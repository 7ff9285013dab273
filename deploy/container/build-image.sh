#!/usr/bin/env bash
# An OCI image of lbsolidd built from Debian packages only (issue 17): no registry is pulled from.
#   deploy/container/build-image.sh [BUILD_DIR] [TAG]    (defaults: ./build, lbsolid:<version>)
# 1. the project's Debian package, made by cpack from BUILD_DIR (cmake/packaging.cmake);
# 2. a Debian 12 minbase root file system from debootstrap, from this machine's own Debian mirror
#    (/etc/apt/sources.list.d/debian.sources, else deb.debian.org);
# 3. the package installed into it with apt, which brings its Depends from the same mirror;
# 4. a non-root user lbsolid (65532:65532, the Kubernetes manifest's) owning /var/lib/lbsolid;
# 5. the tree imported with `podman import`: USER 65532, ENTRYPOINT lbsolidd, a CMD that serves
#    0.0.0.0:50051 with TLS and tokens from /etc/lbsolid (the manifest's mounts; on any other
#    address without TLS the daemon refuses to start), VOLUME /var/lib/lbsolid.
# Needs root (debootstrap, chroot), debootstrap and podman (deploy/container/README.md).
set -euo pipefail
source_dir=$(cd "$(dirname "$0")/../.." && pwd)
build=$(cd "${1:-$source_dir/build}" && pwd)
fail() { echo "build-image: $*" >&2; exit 1; }
[ "$(id -u)" = 0 ] || fail "needs root (debootstrap and chroot)"
for tool in debootstrap podman cpack; do command -v "$tool" >/dev/null || fail "$tool not found"; done
work=$(mktemp -d)
rootfs="$work/rootfs"
cleanup() {
  mountpoint -q "$rootfs/proc" && umount "$rootfs/proc"
  rm -rf "$work"
}
trap cleanup EXIT

(cd "$build" && cpack -G DEB -B "$work/package" >"$work/cpack.log" 2>&1) || { cat "$work/cpack.log"; fail "cpack failed"; }
deb=$(ls "$work"/package/lbsolid_*.deb)
version=$(dpkg-deb -f "$deb" Version)
tag=${2:-lbsolid:$version}
mirror=$(sed -n 's/^URIs: *\(http[^ ]*debian\)$/\1/p' /etc/apt/sources.list.d/debian.sources 2>/dev/null | head -n 1)
mirror=${mirror:-http://deb.debian.org/debian}
echo "build-image: $(basename "$deb"), Debian 12 from $mirror"

debootstrap --variant=minbase bookworm "$rootfs" "$mirror" >"$work/debootstrap.log" 2>&1 ||
  { tail -n 20 "$work/debootstrap.log"; fail "debootstrap failed"; }
cp "$deb" "$rootfs/tmp/lbsolid.deb"
mount -t proc proc "$rootfs/proc"
chroot "$rootfs" /bin/sh -ec '
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends /tmp/lbsolid.deb
  groupadd --gid 65532 lbsolid
  useradd --uid 65532 --gid 65532 --home-dir /var/lib/lbsolid --no-create-home --shell /usr/sbin/nologin lbsolid
  mkdir -p /var/lib/lbsolid /etc/lbsolid/tls /etc/lbsolid/tokens
  chown lbsolid:lbsolid /var/lib/lbsolid
  apt-get clean
  rm -rf /var/lib/apt/lists/* /tmp/lbsolid.deb
' >"$work/install.log" 2>&1 || { tail -n 30 "$work/install.log"; fail "installing the package failed"; }
umount "$rootfs/proc"
chroot "$rootfs" /usr/bin/lbsolidd --version | grep -q "$version" || fail "lbsolidd in the image does not run"

tar --numeric-owner -C "$rootfs" -c . |
  podman import \
    --change 'USER 65532:65532' \
    --change 'WORKDIR /var/lib/lbsolid' \
    --change 'ENTRYPOINT ["/usr/bin/lbsolidd"]' \
    --change 'CMD ["--listen=0.0.0.0:50051", "--data_dir=/var/lib/lbsolid", "--tls_cert=/etc/lbsolid/tls/tls.crt", "--tls_key=/etc/lbsolid/tls/tls.key", "--tokens_file=/etc/lbsolid/tokens/tokens"]' \
    --change 'EXPOSE 50051' \
    --change 'VOLUME /var/lib/lbsolid' \
    --change "LABEL org.opencontainers.image.title=lbsolid org.opencontainers.image.version=$version" \
    - "$tag" >/dev/null
echo "build-image: $tag ($(podman image inspect --format '{{.Size}}' "$tag") bytes)"
