#!/usr/bin/env bash
# The rapier patch (vendor/rapier3d, see vendor/PATCH.md) against rapier3d as
# published on crates.io.
#
#   bash scripts/rapier_patch.sh check            # the committed diff is vendor/rapier3d/src
#                                                 # against rapier3d 0.36.1 as published
#   bash scripts/rapier_patch.sh diff             # rewrite vendor/rapier3d-0.36.1-scasm.diff from them
#   bash scripts/rapier_patch.sh reapply VERSION  # apply the diff onto rapier3d VERSION, in
#                                                 # target/rapier-VERSION-scasm; say what conflicts
#   bash scripts/rapier_patch.sh test             # rapier's own unit tests on the patched crate
#
# Published crates are fetched from static.crates.io into target/rapier-upstream (once).
set -euo pipefail
cd "$(dirname "$0")/.."
base=0.36.1
patch_file=vendor/rapier3d-$base-scasm.diff
work=target/rapier-upstream
mkdir -p "$work"

# The unpacked crate of rapier3d VERSION, fetched once.
fetch() {
    local dir=$work/rapier3d-$1
    if [ ! -d "$dir" ]; then
        mkdir -p "$work"
        # python3, not curl: a fresh machine has python3 and may lack curl.
        python3 -c 'import sys, urllib.request; urllib.request.urlretrieve(sys.argv[1], sys.argv[2])' \
            "https://static.crates.io/crates/rapier3d/rapier3d-$1.crate" "$work/rapier3d-$1.crate" ||
            { echo "rapier_patch: could not fetch rapier3d $1 from static.crates.io" >&2; exit 1; }
        tar -xzf "$work/rapier3d-$1.crate" -C "$work"
    fi
    echo "$dir"
}

# The diff of the published crate's src/ against the vendored src/, paths as
# a/src/... and b/src/..., without timestamps (so the same trees give the same file).
current_diff() {
    local upstream
    upstream=$(fetch "$base")
    rm -rf "$work/a" "$work/b"
    mkdir -p "$work/a" "$work/b"
    cp -r "$upstream/src" "$work/a/src"
    cp -r vendor/rapier3d/src "$work/b/src"
    (cd "$work" && LC_ALL=C diff -ruN a/src b/src || [ $? -eq 1 ]) |
        sed -E 's/^((---|\+\+\+) [^\t]*)\t.*$/\1/'
}

case "${1:-}" in
check)
    current_diff > "$work/current.diff"
    if ! diff -q <(sed -E 's/^((---|\+\+\+) [^\t]*)\t.*$/\1/' "$patch_file") "$work/current.diff" > /dev/null; then
        echo "rapier_patch: $patch_file is not vendor/rapier3d/src against rapier3d $base as published;"
        echo "run 'bash scripts/rapier_patch.sh diff' and commit it"
        exit 1
    fi
    files=$(grep -c '^diff ' "$patch_file")
    echo "rapier_patch: $patch_file is the vendored crate's change to rapier3d $base ($files files)"
    ;;
diff)
    current_diff > "$patch_file"
    echo "rapier_patch: wrote $patch_file ($(grep -c '^diff ' "$patch_file") files)"
    ;;
reapply)
    version=${2:?"usage: rapier_patch.sh reapply VERSION (a published rapier3d, such as 0.37.0)"}
    upstream=$(fetch "$version")
    out=target/rapier-$version-scasm
    rm -rf "$out"
    cp -r "$upstream" "$out"
    # Every hunk that does not apply is written beside its file as FILE.rej.
    set +e
    (cd "$out" && patch -p1 --forward --no-backup-if-mismatch < "$OLDPWD/$patch_file") > "$out/patch.log" 2>&1
    status=$?
    set -e
    applied=$(grep -c '^patching file' "$out/patch.log" || true)
    moved=$(grep -c 'succeeded at .*(offset\|with fuzz' "$out/patch.log" || true)
    failed=$(grep -c 'FAILED at' "$out/patch.log" || true)
    echo "rapier_patch: onto rapier3d $version in $out: $applied files, $moved hunks moved or fuzzed," \
        "$failed hunks failed (log: $out/patch.log)"
    if [ "$status" -ne 0 ]; then
        echo "conflicts (each hunk that failed is in the file's .rej, to redo by hand):"
        (cd "$out" && find src -name '*.rej' | sort | while read -r rej; do
            echo "  ${rej%.rej}: $(grep -c '^@@' "$rej") hunks"
        done)
        exit 1
    fi
    # A patch that applies may still not build against the new crate's code. (The copy is
    # a workspace of its own, not a member of this one.)
    printf '\n[workspace]\n' >> "$out/Cargo.toml"
    if ! cargo check --quiet --lib --manifest-path "$out/Cargo.toml" --target-dir target/rapier-tests \
        > "$out/check.log" 2>&1; then
        echo "the patch applies but does not build: $(grep -c '^error' "$out/check.log") errors" \
            "(log: $out/check.log; the first:)"
        grep -m 5 -A 3 '^error' "$out/check.log" | sed 's/^/  /'
        exit 1
    fi
    echo "the patch applies and builds; next: point [patch.crates-io] at $out, run the fingerprint"
    echo "and rapier's tests there ('cargo test --release --lib --features serde-serialize,fem,block-solver')"
    ;;
test)
    # rapier's own unit tests (inside its src/, the patch's beside them) on the patched crate,
    # with the features that reach the tests of a 3-D build; dependencies pinned by
    # vendor/rapier3d/Cargo.lock.
    cargo test --release --locked --lib --manifest-path vendor/rapier3d/Cargo.toml \
        --features serde-serialize,fem,block-solver --target-dir target/rapier-tests
    ;;
*)
    sed -n '2,12p' "$0" | sed 's/^# \{0,1\}//'
    exit 2
    ;;
esac
