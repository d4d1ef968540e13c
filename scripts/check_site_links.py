"""Checks every link of the built documentation site (`scripts/docs.sh` runs it).

Every `href`/`src` without a scheme must name a file of the site, and an `#anchor` an `id` in
that file; a MyST reference that Sphinx could not resolve (rendered as a bare `xref myst` span,
without a warning) is an error too. External links (http, https, mailto) are listed, not
fetched: the machines that build the site have no internet. Exits 1 naming each broken link.
"""

import html.parser
import pathlib
import sys
import urllib.parse


class Page(html.parser.HTMLParser):
    def __init__(self):
        super().__init__()
        self.links, self.ids, self.unresolved = [], set(), 0

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if "id" in a:
            self.ids.add(a["id"])
        if tag == "a" and "name" in a:
            self.ids.add(a["name"])
        for key in ("href", "src"):
            if a.get(key):
                self.links.append(a[key])
        classes = set((a.get("class") or "").split())
        if tag == "span" and {"xref", "myst"} <= classes and "download" not in classes:
            self.unresolved += 1


def parse(path, cache):
    if path not in cache:
        p = Page()
        p.feed(path.read_text(encoding="utf-8", errors="replace"))
        cache[path] = p
    return cache[path]


def main(root):
    root = pathlib.Path(root).resolve()
    cache, broken, external, checked = {}, [], set(), 0
    # The Rust API (cargo doc) has its own checked links; only the pages Sphinx made are walked.
    pages = [p for p in root.rglob("*.html") if "reference/rust/" not in p.as_posix()]
    for page in pages:
        doc = parse(page, cache)
        if doc.unresolved:
            broken.append(f"{page.relative_to(root)}: {doc.unresolved} unresolved reference(s)")
        for link in doc.links:
            url = urllib.parse.urlsplit(link)
            if url.scheme or link.startswith("//"):
                external.add(link)
                continue
            target = (page.parent / urllib.parse.unquote(url.path)).resolve() if url.path else page
            checked += 1
            if target.is_dir():
                target = target / "index.html"
            if not target.is_file():
                broken.append(f"{page.relative_to(root)}: {link} (no such file)")
            elif url.fragment and target.suffix == ".html" and "reference/rust/" not in target.as_posix():
                if url.fragment not in parse(target, cache).ids:
                    broken.append(f"{page.relative_to(root)}: {link} (no such anchor)")
    for b in broken:
        print("broken link:", b, file=sys.stderr)
    print(f"{len(pages)} pages, {checked} local links checked, {len(broken)} broken, "
          f"{len(external)} external links not fetched (no internet)")
    return 1 if broken else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1] if len(sys.argv) > 1 else "target/docs/html"))
