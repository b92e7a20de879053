#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""docs/paraview.md lists every proxy of Modules/ParaView/MorphNode.xml, and nothing else.

Each proxy (SourceProxy or WriterProxy) must have a row of the docs' proxy table naming its
class and the name pvpython gives it: the label without spaces and hyphens for sources and
filters, the proxy name for writers. Usage: CheckParaViewDocs.py MorphNode.xml paraview.md
"""
import re
import sys
import xml.etree.ElementTree as ET


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
    for fault in faults:
        print(fault)
    print(f"{len(proxies)} proxies in the plugin, {len(rows)} rows in the docs")
    return 1 if faults or not proxies else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], sys.argv[2]))
