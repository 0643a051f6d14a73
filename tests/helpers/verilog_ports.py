"""The ports of a module as its generated Verilog declares them, read from the text (what a
Verilog reader sees, independent of the manifest and of the Amaranth signature)."""

import re


def declared_ports(text: str, module: str) -> dict[str, tuple[str, int]]:
    """``{name: (direction, width)}`` of the ports of ``module`` in Amaranth's Verilog
    (``input [7:0] name;`` declarations; every name of the module header declared once)."""
    body = text[text.index(f"module {module}("):]
    body = body[:body.index("endmodule")]
    header = body[:body.index(");")]
    names = [n.strip() for n in header[header.index("(") + 1:].split(",")]
    declarations = re.findall(r"^\s*(input|output)\s+(?:\[(\d+):0\]\s+)?(\S+);", body,
                              flags=re.M)
    ports = {name: (direction, int(msb) + 1 if msb else 1)
             for direction, msb, name in declarations}
    assert len(declarations) == len(ports) and sorted(ports) == sorted(names)
    return ports
