#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""docs/paraview.md lists every proxy of Modules/ParaView/MorphNode.xml, and nothing else.

Each proxy (SourceProxy or WriterProxy) must have a row of the docs' proxy table naming its
class and the name pvpython gives it: the label without spaces and hyphens for sources and
filters, the proxy name for writers. Every public class of the VTK modules (the CLASSES of
Modules/MorphNode/*/CMakeLists.txt, beside the plugin's folder) that no proxy wraps must be
named in the docs' list of classes without a proxy (the paragraph "... have no proxy, on
purpose" and its bullets). Usage: CheckParaViewDocs.py MorphNode.xml paraview.md
"""
import glob
import os
import re
import sys
import xml.etree.ElementTree as ET


def public_classes(xml_path):
    """The CLASSES of every Modules/MorphNode/<Concept>/CMakeLists.txt."""
    root = os.path.join(os.path.dirname(os.path.abspath(xml_path)), "..", "MorphNode")
    classes = []
    for path in sorted(glob.glob(os.path.join(root, "*", "CMakeLists.txt"))):
        text = re.sub(r"#[^\n]*", "", open(path, encoding="utf-8").read())
        match = re.search(r"vtk_module_add_module\((.*?)\)", text, re.S)
        section = None
        for word in match.group(1).split()[1:] if match else []:
            if word in ("CLASSES", "SOURCES", "PRIVATE_HEADERS", "HEADERS", "TEMPLATES"):
                section = word
            elif section == "CLASSES":
                classes.append(word)
    return classes


def without_proxy(md_path):
    """The classes the docs name as having no proxy: from the line saying so to the end of
    the bullet list after it."""
    named, on, seen_bullet = set(), False, False
    for line in open(md_path, encoding="utf-8"):
        if "have no proxy, on purpose" in line:
            on = True
        if not on:
            continue
        if line.startswith("- "):
            seen_bullet = True
        elif seen_bullet and line.strip() and not line.startswith(" "):
            break
        named.update(re.findall(r"`(vtk\w+)`", line))
    return named


def main(xml_path, md_path):
    proxies = []
    for group in ET.parse(xml_path).getroot().iter("ProxyGroup"):
        for proxy in group:
            if proxy.tag not in ("SourceProxy", "WriterProxy"):
                continue
            label = proxy.get("label", proxy.get("name"))
            name = proxy.get("name") if proxy.tag == "WriterProxy" else re.sub(r"[ \-]", "", label)
            proxies.append((name, proxy.get("class")))
    rows = {}
    for line in open(md_path, encoding="utf-8"):
        match = re.match(r"^\| `(\w+)` \(.*?\| `(vtk\w+)` \|", line)
        if match:
            rows[match.group(1)] = match.group(2)
    faults = []
    for name, cls in proxies:
        if name not in rows:
            faults.append(f"{md_path}: no row for the proxy `{name}` ({cls})")
        elif rows[name] != cls:
            faults.append(f"{md_path}: the row of `{name}` names `{rows[name]}`, the plugin {cls}")
    known = {name for name, _ in proxies}
    faults += [f"{md_path}: `{name}` is no proxy of {xml_path}" for name in rows if name not in known]
    classes = {cls for _, cls in proxies}
    excepted = without_proxy(md_path)
    for cls in public_classes(xml_path):
        if cls not in classes and cls not in excepted:
            faults.append(f"{md_path}: the public class `{cls}` has no proxy and is not named "
                          "among the classes without one")
    for fault in faults:
        print(fault)
    print(f"{len(proxies)} proxies in the plugin, {len(rows)} rows in the docs")
    return 1 if faults or not proxies else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], sys.argv[2]))
