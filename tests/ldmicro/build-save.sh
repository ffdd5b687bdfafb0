#!/bin/bash
# LDmicro 5.4.1.1 with one batch command added, `ldmicro.exe /s IN.ld OUT.ld`: load the file and
# save it as LDmicro saves it (save-command.patch beside this script). The oracle of
# tests/test_ldmicro_saves.py, built from ../shared's source by ../shared's build.sh into
# /opt/ldmicro-save (LDMICRO_SAVE_PREFIX), beside the unpatched /opt/ldmicro.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
tools=${LDMICRO_TOOLS:-$(cd "$here/../../../shared/tools/ldmicro" && pwd)}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
tar -xzf "$tools/ldmicro-5.4.1.1-src.tar.gz" -C "$work"
patch -s -d "$work/ldmicro-5.4.1.1" -p1 < "$here/save-command.patch"
tar -czf "$work/ldmicro-save-src.tar.gz" -C "$work" ldmicro-5.4.1.1
LDMICRO_PREFIX=${LDMICRO_SAVE_PREFIX:-/opt/ldmicro-save} LDMICRO_BUILD_DIR="$work/build" \
    bash "$tools/build.sh" "$work/ldmicro-save-src.tar.gz"
