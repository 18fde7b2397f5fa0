#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Installs the Debian package into a clean Debian root and uses it there as a new user would:
#   apt-get install ./talus_<version>_<arch>.deb (which fetches its Depends from the mirror),
#   talus --version, the example bounce.lua, require() of every installed Lua library, the same
#   example again without /proc (talus then finds itself on PATH), an out-of-tree build of the
#   plugin template against the installed SDK whose model a script then loads by name, and
#   apt-get remove talus.
# The root is made by debootstrap (minbase) in a scratch directory and deleted at the end. Needs
# root, debootstrap (apt-get install debootstrap) and a Debian mirror: about 4 minutes and 700 MB
# of disk with the compiler for the plugin build (--no-plugin: less than half of that).
#
#   scripts/check_deb.sh [--no-plugin] [--keep] [talus_*.deb]
#
# Without a package argument it always packages the build as it is now: cpack -G DEB on
# ${TALUS_BUILD_DIR:-build} (which first brings the build up to date, as `make` would), into a
# scratch directory, so that no older talus_*.deb lying about is ever the one tested.
# TALUS_DEBIAN_MIRROR overrides the mirror (default http://deb.debian.org/debian); the suite is
# this machine's (VERSION_CODENAME in /etc/os-release).
set -euo pipefail
cd "$(dirname "$0")/.."

plugin=1
keep=0
deb=""
for a in "$@"; do
    case "$a" in
        --no-plugin) plugin=0 ;;
        --keep) keep=1 ;;
        -*) echo "check_deb: unknown option $a" >&2; exit 2 ;;
        *) deb="$a" ;;
    esac
done
[[ $(id -u) -eq 0 ]] || { echo "check_deb: run as root (debootstrap, chroot)" >&2; exit 1; }
command -v debootstrap >/dev/null ||
    { echo "check_deb: needs debootstrap (apt-get install debootstrap)" >&2; exit 1; }
pkgdir=""  # the package made here, if any (a package given is left alone)
root=""
cleanup() {
    if [[ -n $root ]]; then
        mountpoint -q "$root/dev/pts" && umount "$root/dev/pts"
        mountpoint -q "$root/proc" && umount "$root/proc"
        if ((keep)); then echo "check_deb: kept $root"; else rm -rf "$root"; fi
    fi
    if [[ -n $pkgdir ]]; then
        if ((keep)); then echo "check_deb: kept $pkgdir"; else rm -rf "$pkgdir"; fi
    fi
}
trap cleanup EXIT
if [[ -z $deb ]]; then
    build=${TALUS_BUILD_DIR:-build}
    [[ -f $build/CPackConfig.cmake ]] ||
        { echo "check_deb: no configured build in $build/ (scripts/build.sh first)" >&2; exit 1; }
    type=$(sed -n 's/^CMAKE_BUILD_TYPE:[A-Z]*=//p' "$build/CMakeCache.txt")
    [[ $type == Release ]] ||
        echo "check_deb: warning: $build/ is a ${type:-no-type} build, not Release" >&2
    pkgdir=$(mktemp -d "${TMPDIR:-/tmp}/talus-deb.XXXXXX")
    echo "check_deb: cpack -G DEB on $build/ into $pkgdir"
    if ! cpack -G DEB --config "$build/CPackConfig.cmake" -B "$pkgdir" >"$pkgdir/cpack.log" 2>&1; then
        tail -30 "$pkgdir/cpack.log" >&2
        exit 1
    fi
    shopt -s nullglob
    debs=("$pkgdir"/talus_*.deb)
    shopt -u nullglob
    if ((${#debs[@]} != 1)); then
        echo "check_deb: cpack made ${#debs[@]} packages in $pkgdir:" >&2
        tail -30 "$pkgdir/cpack.log" >&2
        exit 1
    fi
    deb=${debs[0]}
fi
[[ -f $deb ]] || { echo "check_deb: no such package $deb" >&2; exit 1; }
deb=$(realpath "$deb")
# shellcheck source=/dev/null
. /etc/os-release
suite=${VERSION_CODENAME:?no VERSION_CODENAME in /etc/os-release}
mirror=${TALUS_DEBIAN_MIRROR:-http://deb.debian.org/debian}

root=$(mktemp -d "${TMPDIR:-/tmp}/talus-clean-root.XXXXXX")
chmod 755 "$root"  # apt downloads as the user _apt, who must reach the root's directories
in_root() { chroot "$root" env -i PATH=/usr/sbin:/usr/bin:/sbin:/bin HOME=/root \
    DEBIAN_FRONTEND=noninteractive "$@"; }
step() { echo "check_deb: $*"; }

step "debootstrap $suite (minbase) into $root"
debootstrap --variant=minbase "$suite" "$root" "$mirror" >"$root.log" 2>&1 ||
    { tail -20 "$root.log" >&2; rm -f "$root.log"; exit 1; }
rm -f "$root.log"
cp /etc/resolv.conf "$root/etc/resolv.conf"
cp "$deb" "$root/tmp/"
mount -t proc proc "$root/proc"
mount -t devpts devpts "$root/dev/pts"  # dpkg's log of the terminal

step "apt-get install ./$(basename "$deb")"
in_root apt-get update -qq
in_root sh -c "cd /tmp && apt-get install -y -qq --no-install-recommends ./$(basename "$deb")" \
    >/dev/null
in_root talus --version

step "the example bounce.lua"
in_root sh -c 'cd /tmp && talus run /usr/share/talus/scripts/examples/bounce.lua out' |
    grep "exact restitution"

step "require every installed Lua library"
modules=$(cd "$root/usr/share/talus/scripts/lib" && find . -name '*.lua' | sort |
    sed -e 's|^\./||' -e 's|\.lua$||' -e 's|/init$||' -e 's|/|.|g')
cat >"$root/tmp/require_all.lua" <<'LUA'
for _, name in ipairs(arg) do
    local file = package.searchpath(name, package.path)
    assert(file and file:find("^/usr/share/talus/scripts/lib/"), name .. " found at " .. tostring(file))
    require(name)
end
print(#arg .. " modules loaded from /usr/share/talus/scripts/lib")
LUA
# shellcheck disable=SC2086
in_root talus run /tmp/require_all.lua $modules

step "without /proc: talus finds its plugins through PATH"
umount "$root/proc"
in_root sh -c 'cd /tmp && talus run /usr/share/talus/scripts/examples/bounce.lua out2' |
    grep "exact restitution"
mount -t proc proc "$root/proc"

if ((plugin)); then
    step "an out-of-tree plugin from /usr/share/talus/plugin-template"
    in_root apt-get install -y -qq --no-install-recommends cmake g++ make >/dev/null
    cat >"$root/tmp/use_null.lua" <<'LUA'
local m = talus.model{}
m:contact_model("null", {})
local lib = talus.contact_model_info("null").library
assert(lib == "/tmp/mymodel/build/libtalus_null.so", "null loaded from " .. tostring(lib))
print("null loaded by name from " .. lib)
LUA
    in_root sh -c 'cp -r /usr/share/talus/plugin-template /tmp/mymodel &&
        cmake -S /tmp/mymodel -B /tmp/mymodel/build -DCMAKE_BUILD_TYPE=Release >/dev/null &&
        cmake --build /tmp/mymodel/build >/dev/null &&
        grep "^talus_DIR" /tmp/mymodel/build/CMakeCache.txt &&
        TALUS_PLUGIN_PATH=/tmp/mymodel/build talus run /tmp/use_null.lua'
fi

step "apt-get remove talus"
in_root apt-get remove -y -qq talus >/dev/null
if [[ -e $root/usr/bin/talus || -e $root/usr/lib/talus ]]; then
    echo "check_deb: files left after apt-get remove" >&2
    exit 1
fi
step "passed"
