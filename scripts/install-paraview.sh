#!/usr/bin/env bash
# Installs ParaView's pvbatch (Debian 12 packages) for scripts/render-frames.sh without touching
# the development stack; quiet and quick when everything is there. See scripts/PARAVIEW.md.
#
# Debian's python3-paraview declares "Conflicts: python3-vtk9" (both ship vtkmodules/ in
# /usr/lib/python3/dist-packages), and libvtk9-dev depends on python3-vtk9, so apt would remove
# libvtk9-dev. Instead:
#   - apt installs (manually, as ordinary packages) everything paraview depends on, plus xvfb
#     and xauth: none of these conflicts with anything;
#   - the paraview and python3-paraview .debs themselves are only downloaded and unpacked with
#     dpkg-deb -x into a private prefix (default /opt/flexsens-paraview), which dpkg does not
#     know about: /usr/lib/python3/dist-packages/vtkmodules stays python3-vtk9's.
# Environment: FLEXSENS_PARAVIEW_PREFIX overrides the prefix.
set -euo pipefail
PREFIX="${FLEXSENS_PARAVIEW_PREFIX:-/opt/flexsens-paraview}"
PV_PACKAGES=(paraview python3-paraview)     # unpacked privately, never installed with dpkg
EXTRA=(xvfb xauth fonts-dejavu-core)        # headless X server for pvbatch (Debian's is GLX-only), font
RENDER="$(cd "$(dirname "$0")" && pwd)/render-frames.sh"

die() { echo "install-paraview: $*" >&2; exit 1; }

[ "$(id -u)" = 0 ] || die "must run as root (apt-get install, writes $PREFIX)"
for tool in apt-get apt-cache dpkg-deb dpkg-query; do
  command -v "$tool" >/dev/null || die "needs Debian's $tool"
done

# --- fast path: prefix unpacked, its recorded dependencies and xvfb all installed ---------
if [ -f "$PREFIX/.flexsens-installed" ] && [ -f "$PREFIX/.flexsens-depends" ]; then
  mapfile -t want < <(grep . "$PREFIX/.flexsens-depends")
  want+=("${EXTRA[@]}")
  have="$(dpkg-query -W -f='${Status}\n' "${want[@]}" 2>/dev/null | grep -c "install ok installed" || true)"
  [ "$have" = "${#want[@]}" ] && exit 0
fi

export DEBIAN_FRONTEND=noninteractive
echo "install-paraview: installing ParaView (pvbatch) into $PREFIX" >&2
apt-get update -qq || die "apt-get update failed (no network to the Debian mirror?)"
apt-cache show paraview >/dev/null 2>&1 || die "no 'paraview' package in the apt sources"

# --- 1. runtime dependencies via apt ------------------------------------------------------
# What apt would install for 'paraview' (its Depends only; paraview itself does not conflict
# with python3-vtk9, python3-paraview's Depends are a subset of paraview's), minus paraview.
sim="$(apt-get install -s --no-install-recommends paraview "${EXTRA[@]}" 2>&1)" ||
  die "apt cannot resolve paraview's dependencies:"$'\n'"$sim"
if grep -q '^Remv' <<<"$sim"; then
  die "installing paraview's dependencies would remove packages:"$'\n'"$(grep '^Remv' <<<"$sim")"
fi
mapfile -t deps < <(awk '/^Inst /{print $2}' <<<"$sim" | grep -vx paraview || true)
if [ ${#deps[@]} -gt 0 ]; then
  apt-get install -y -qq --no-install-recommends "${deps[@]}" >/dev/null ||
    die "apt-get install of paraview's dependencies failed"
fi
# Record the full dependency list (installed or not before) for the fast path.
alldeps="$(apt-cache depends --no-recommends --no-suggests --no-conflicts --no-breaks \
  --no-replaces --no-enhances paraview python3-paraview 2>/dev/null |
  awk '/^ *Depends:/{ if (!alt) print $2; alt = ($1 ~ /^\|/) } /^ *\|Depends:/{ alt = 1 }' |
  grep -v '^<' | grep -vx -e paraview -e python3 | sort -u)" || true

# --- 2. unpack the two ParaView .debs into the private prefix -----------------------------
tmp="$(mktemp -d /tmp/flexsens-paraview.XXXXXX)"
trap 'rm -rf "$tmp"' EXIT
chmod 755 "$tmp"
id _apt >/dev/null 2>&1 && chown _apt "$tmp"   # lets apt download sandboxed, no warning
(cd "$tmp" || exit 1; apt-get download -qq "${PV_PACKAGES[@]}" 2>&1 | grep -v '^W: Download is performed unsandboxed' || true)
for p in "${PV_PACKAGES[@]}"; do
  ls "$tmp"/"${p}"_*.deb >/dev/null 2>&1 || die "apt-get download $p failed"
done
rm -rf "$PREFIX.new"
mkdir -p "$PREFIX.new"
for deb in "$tmp"/*.deb; do dpkg-deb -x "$deb" "$PREFIX.new" || die "dpkg-deb -x $deb failed"; done
version="$(dpkg-deb -f "$tmp"/paraview_*.deb Version)"
printf '%s\n' "$alldeps" > "$PREFIX.new/.flexsens-depends"
rm -rf "$PREFIX.old"
[ -e "$PREFIX" ] && mv "$PREFIX" "$PREFIX.old"
mv "$PREFIX.new" "$PREFIX"
rm -rf "$PREFIX.old"

# --- 3. smoke test: pvbatch renders headless -----------------------------------------------
if ! out="$(FLEXSENS_PARAVIEW_PREFIX="$PREFIX" bash "$RENDER" --selftest 2>&1)"; then
  die "pvbatch does not run from $PREFIX:"$'\n'"$out"
fi
echo "paraview $version" > "$PREFIX/.flexsens-installed"
echo "install-paraview: ParaView $version ready ($out)" >&2
