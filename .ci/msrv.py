#!/usr/bin/env python3
"""Checks that every workspace package's `rust-version` is at least the
`rust-version` of every locked package it builds with.

Reads `cargo metadata --locked` (or a JSON file given with --metadata) and,
for each workspace member, walks its normal and build dependencies (and,
for the tests, its dev-dependencies) through the locked resolve graph.
Fails (exit 1) when a member declares an older Rust than one of its normal
or build dependencies needs, naming both; prints what the tests need.

    python3 .ci/msrv.py               # check the workspace
    python3 .ci/msrv.py --self-test   # prove the check fails on a raised requirement
"""
import argparse
import json
import subprocess
import sys


def version(text):
    """`1.88` or `1.88.0` as a comparable tuple; None for no requirement."""
    if not text:
        return None
    parts = [int(p) for p in text.split(".")]
    return tuple(parts + [0] * (3 - len(parts)))


def show(v):
    return ".".join(str(p) for p in v[:2]) if v[2] == 0 else ".".join(map(str, v))


def reach(nodes, start, kinds):
    """Every package reached from `start`'s deps of `kinds`, then their normal and build deps."""
    seen, stack = set(), []
    for dep in nodes[start]["deps"]:
        if any(k["kind"] in kinds for k in dep["dep_kinds"]):
            stack.append(dep["pkg"])
    while stack:
        pkg = stack.pop()
        if pkg in seen:
            continue
        seen.add(pkg)
        for dep in nodes[pkg]["deps"]:
            if any(k["kind"] in (None, "build") for k in dep["dep_kinds"]):
                stack.append(dep["pkg"])
    return seen


def check(meta):
    """Returns (failures, report lines)."""
    packages = {p["id"]: p for p in meta["packages"]}
    nodes = {n["id"]: n for n in meta["resolve"]["nodes"]}
    failures, lines = [], []
    for member in sorted(meta["workspace_members"], key=lambda i: packages[i]["name"]):
        pkg = packages[member]
        declared = version(pkg.get("rust_version"))
        if declared is None:
            failures.append(f"{pkg['name']}: no rust-version declared")
            continue

        def needs(kinds):
            best = None
            for dep in reach(nodes, member, kinds):
                if dep in meta["workspace_members"]:
                    continue
                v = version(packages[dep].get("rust_version"))
                if v and (best is None or v > best[0]):
                    best = (v, packages[dep]["name"], packages[dep]["version"])
            return best

        normal = needs((None, "build"))
        tests = needs((None, "build", "dev"))
        if normal and normal[0] > declared:
            failures.append(
                f"{pkg['name']} declares rust-version {show(declared)}, but the locked "
                f"{normal[1]} {normal[2]} needs Rust {show(normal[0])}"
            )
        line = f"{pkg['name']}: declares {show(declared)}"
        if normal:
            line += f"; its dependencies need {show(normal[0])} ({normal[1]} {normal[2]})"
        if tests and (not normal or tests[0] > normal[0]):
            line += f"; its tests need {show(tests[0])} ({tests[1]} {tests[2]})"
        lines.append(line)
    return failures, lines


def self_test(meta):
    """Raises one locked normal dependency's requirement past every declaration."""
    members = set(meta["workspace_members"])
    packages = {p["id"]: p for p in meta["packages"]}
    nodes = {n["id"]: n for n in meta["resolve"]["nodes"]}
    target = None
    for member in members:
        for dep in reach(nodes, member, (None, "build")):
            if dep not in members:
                target = dep
                break
        if target:
            break
    packages[target]["rust_version"] = "99.0"
    failures, _ = check(meta)
    failures = [f for f in failures if f" {packages[target]['name']} " in f and "99.0" in f]
    if not failures:
        print(f"self-test FAILED: raising {packages[target]['name']} to Rust 99.0 went unnoticed")
        return 1
    print(f"self-test passed: raising {packages[target]['name']} to Rust 99.0 is refused:")
    print("  " + failures[0])
    return 0


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--metadata", help="a `cargo metadata` JSON file instead of running cargo")
    parser.add_argument("--self-test", action="store_true", help="prove the check fails on a raised requirement")
    args = parser.parse_args()
    if args.metadata:
        with open(args.metadata, encoding="utf-8") as f:
            meta = json.load(f)
    else:
        out = subprocess.run(
            ["cargo", "metadata", "--format-version", "1", "--locked"],
            check=True, capture_output=True, text=True,
        ).stdout
        meta = json.loads(out)
    if args.self_test:
        return self_test(meta)
    failures, lines = check(meta)
    for line in lines:
        print(line)
    if failures:
        print("\nrust-version is older than what is locked:", file=sys.stderr)
        for f in failures:
            print("  " + f, file=sys.stderr)
        return 1
    print("every rust-version covers its locked dependencies")
    return 0


if __name__ == "__main__":
    sys.exit(main())
