#!/usr/bin/env python3
"""Is the library's public API the pinned one? Reads the item list of
`cargo doc -p crestline --no-deps` (target/doc/crestline/all.html: one link per
public item, by its path) and compares it with crates/crestline/public_api.txt.

    python3 tools/public_api.py [--update] [--doc DIR]

Fails (exit 1) with the difference when an item was added or removed, or when
there are more than MAX_ITEMS: growing the API is a decision, taken by updating
the pinned list (`--update` writes it) in the same change.
"""

import argparse
import difflib
import os
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
PINNED = ROOT / "crates" / "crestline" / "public_api.txt"
# The most items the library offers: what a user needs, and nothing else.
MAX_ITEMS = 155


def public_items(all_html: Path) -> list[str]:
    """The items of rustdoc's all.html as paths (`io::read_mesh`), sorted; the
    links to the page's own sections (`#structs`) left out."""
    links = re.findall(r'<li><a href="([^"#][^"]*)"', all_html.read_text())
    items = set()
    for link in links:
        *modules, page = link.removesuffix(".html").split("/")
        items.add("::".join([*modules, page.split(".", 1)[1]]))
    return sorted(items)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--update", action="store_true", help="write the pinned list")
    parser.add_argument(
        "--doc",
        type=Path,
        default=Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target")) / "doc",
        help="the documentation folder (default: doc/ in $CARGO_TARGET_DIR or target/)",
    )
    args = parser.parse_args()
    all_html = args.doc / "crestline" / "all.html"
    if not all_html.is_file():
        print(f"no {all_html}: run `cargo doc -p crestline --no-deps` first")
        return 1
    items = public_items(all_html)
    if args.update:
        PINNED.write_text("".join(f"{item}\n" for item in items))
    pinned = PINNED.read_text().splitlines()
    failed = False
    if items != pinned:
        diff = difflib.unified_diff(
            pinned, items, str(PINNED.relative_to(ROOT)), "cargo doc", lineterm=""
        )
        print("\n".join(diff))
        print(
            "the public API differs from the pinned list: update it with "
            "`python3 tools/public_api.py --update` if the change is meant"
        )
        failed = True
    if len(items) > MAX_ITEMS:
        print(f"{len(items)} public items, more than {MAX_ITEMS}")
        failed = True
    if not failed:
        print(f"public API as pinned: {len(items)} items")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
