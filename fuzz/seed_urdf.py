#!/usr/bin/env python3
"""Writes structured seeds for the urdf_robot target into fuzz/corpus/urdf_robot/gen-*.urdf.

Why: session 16's campaign of 1.37 M executions still found new edges at a steady rate, and
libFuzzer's -print_coverage showed where — in the XML reader's character references (digits of
every length, every UTF-8 width), and in the loops over a robot's joints (a chain, a star, a mimic
chain, a loop of links), whose hit counts are features by powers of two. A mutator reaches a
65-joint chain or `&#x10FFFF;` byte by byte; these seeds start it there. Each seed is a valid
robot or one kind of refusal (docs/errors.md), so that the merged corpus keeps it only if it
reaches something the others do not.

    python3 fuzz/seed_urdf.py            # (re)writes the gen-* seeds
"""
import pathlib

OUT = pathlib.Path(__file__).resolve().parent / "corpus" / "urdf_robot"

SHAPES = [
    '<box size="0.1 0.2 0.3"/>',
    '<cylinder radius="0.05" length="0.2"/>',
    '<sphere radius="0.04"/>',
    '<mesh filename="package://arm3_description/meshes/tri.obj" scale="0.5 0.5 0.5"/>',
    '<mesh filename="meshes/small_motor.obj" scale="0.1 0.1 0.1"/>',
]


def link(name, shape=None, origin=""):
    if shape is None:
        return f'<link name="{name}"/>'
    return (f'<link name="{name}"><visual>{origin}<geometry>{shape}</geometry>'
            f'</visual></link>')


def joint(name, parent, child, kind="revolute", axis="0 0 1", limits=(-1, 1), mimic=None,
          origin='<origin xyz="0 0 0.1" rpy="0 0 0"/>'):
    parts = [f'<joint name="{name}" type="{kind}">', f'<parent link="{parent}"/>',
             f'<child link="{child}"/>', origin]
    if axis is not None:
        parts.append(f'<axis xyz="{axis}"/>')
    if limits is not None:
        parts.append(f'<limit lower="{limits[0]}" upper="{limits[1]}" effort="1" velocity="1"/>')
    if mimic is not None:
        parts.append(f'<mimic joint="{mimic[0]}" multiplier="{mimic[1]}" offset="{mimic[2]}"/>')
    parts.append("</joint>")
    return "".join(parts)


def robot(body, name="r", prolog='<?xml version="1.0"?>\n'):
    return f'{prolog}<robot name="{name}">\n' + "\n".join(body) + "\n</robot>\n"


def chain(n, kinds=("revolute",), shape_every=1):
    body = [link("l0", SHAPES[0])]
    for i in range(1, n + 1):
        kind = kinds[i % len(kinds)]
        limits = (-1, 1) if kind in ("revolute", "prismatic") else None
        body.append(joint(f"j{i}", f"l{i - 1}", f"l{i}", kind, limits=limits))
        body.append(link(f"l{i}", SHAPES[i % len(SHAPES)] if i % shape_every == 0 else None))
    return body


def seeds():
    out = {}
    sizes = [1, 2, 3, 5, 9, 17, 33, 65, 130, 260]
    kinds = ("revolute", "continuous", "prismatic", "fixed", "floating", "planar")
    for n in sizes:
        out[f"chain-{n}"] = robot(chain(n, kinds, shape_every=max(1, n // 8)))
        # A star: one link with n children (a link's child joints, the breadth-first walk).
        body = [link("hub", SHAPES[1])]
        for i in range(n):
            body.append(joint(f"s{i}", "hub", f"leaf{i}", "continuous", limits=None))
            body.append(link(f"leaf{i}", SHAPES[2] if i % 4 == 0 else None))
        out[f"star-{n}"] = robot(body)
        # A chain of mimics: each joint follows the one before, the first is settable.
        body = [link("l0")]
        for i in range(1, n + 1):
            mimic = None if i == 1 else (f"j{i - 1}", -0.5 if i % 2 else 2, 0.1 * i)
            body.append(joint(f"j{i}", f"l{i - 1}", f"l{i}", mimic=mimic, origin=""))
            body.append(link(f"l{i}"))
        out[f"mimic-chain-{n}"] = robot(body)
        # A cycle of mimics among n joints (refused: "mimics itself through").
        body = [link("l0")]
        for i in range(1, n + 1):
            followed = f"j{i % n + 1}"
            body.append(joint(f"j{i}", f"l{i - 1}", f"l{i}", mimic=(followed, 1, 0), origin=""))
            body.append(link(f"l{i}"))
        out[f"mimic-cycle-{n}"] = robot(body)
        # A loop of links (refused: "closes a loop of links"), beside a root with a chain.
        if n >= 2:
            body = [link("root"), joint("to_a0", "root", "b0"), link("b0")]
            for i in range(n):
                body.append(joint(f"loop{i}", f"a{i}", f"a{(i + 1) % n}", origin=""))
                body.append(link(f"a{i}"))
            out[f"link-loop-{n}"] = robot(body)
    # Spheres and cylinders across sizes: their tessellation (and every loop over a visual's
    # triangles after it: scale, checks, transforms, the state's re-posing) runs a different
    # number of times for each, hit counts the campaigns otherwise reach one ChangeASCIIInt at a
    # time (session 17's log: jumps of 40 to 60 features from one changed radius).
    for radius in ["0.001", "0.003", "0.01", "0.03", "0.1", "0.3", "1", "3", "10"]:
        out[f"sizes-{radius}"] = robot([
            link("base", f'<sphere radius="{radius}"/>'),
            joint("j", "base", "arm", limits=(-1, 1)),
            link("arm", f'<cylinder radius="{radius}" length="{radius}"/>')])
    # Refusals of the joints' tree and of urdfdom.
    out["self-joint"] = robot([link("a"), joint("j", "a", "a")])
    out["two-parents"] = robot([link("a"), link("b"), link("c"), joint("j1", "a", "c"),
                                joint("j2", "b", "c")])
    out["no-links"] = robot([])
    out["two-roots"] = robot([link("a"), link("b")])
    out["missing-child"] = robot([link("a"), joint("j", "a", "ghost")])
    out["missing-parent"] = robot([link("a"), joint("j", "ghost", "a")])
    out["joint-no-name"] = robot([link("a"), link("b"),
                                  '<joint type="fixed"><parent link="a"/><child link="b"/></joint>'])
    out["joint-no-type"] = robot([link("a"), link("b"),
                                  '<joint name="j"><parent link="a"/><child link="b"/></joint>'])
    out["joint-bad-type"] = robot([link("a"), link("b"), joint("j", "a", "b", "hinge")])
    out["revolute-no-limit"] = robot([link("a"), link("b"), joint("j", "a", "b", limits=None)])
    out["zero-axis"] = robot([link("a"), link("b"), joint("j", "a", "b", axis="0 0 0")])
    out["tiny-axis"] = robot([link("a"), link("b"), joint("j", "a", "b", axis="1e-13 0 0")])
    out["bad-axis"] = robot([link("a"), link("b"), joint("j", "a", "b", axis="1 0")])
    out["limits-reversed"] = robot([link("a"), link("b"), joint("j", "a", "b", limits=(1, -1))])
    out["limits-huge"] = robot([link("a"), link("b"),
                                joint("j", "a", "b", "prismatic", limits=("-1e308", "1e308"))])
    out["mimic-missing"] = robot([link("a"), link("b"),
                                  joint("j", "a", "b", mimic=("ghost", 1, 0))])
    out["mimic-of-fixed"] = robot([link("a"), link("b"), link("c"),
                                   joint("f", "a", "b", "fixed", limits=None),
                                   joint("j", "b", "c", mimic=("f", 1, 0))])
    out["duplicate-link"] = robot([link("a"), link("a")])
    out["duplicate-joint"] = robot([link("a"), link("b"), link("c"), joint("j", "a", "b"),
                                    joint("j", "b", "c")])
    # Visuals: every shape, several per link, origins, materials, and what urdfdom cannot parse.
    body = [link("base")]
    for i, shape in enumerate(SHAPES):
        body.append(joint(f"j{i}", "base", f"v{i}", "fixed", limits=None))
        body.append(f'<link name="v{i}"><visual><origin xyz="0.1 0 0" rpy="0.1 0.2 0.3"/>'
                    f'<geometry>{shape}</geometry><material name="m{i}"><color rgba="1 0 0 1"/>'
                    f'</material></visual><visual><geometry>{SHAPES[(i + 1) % 5]}</geometry>'
                    f'</visual><collision><geometry>{shape}</geometry></collision></link>')
    out["visuals"] = robot(body)
    bad_visuals = {
        "box-two-numbers": '<box size="1 1"/>',
        "sphere-no-radius": "<sphere/>",
        "cylinder-no-length": '<cylinder radius="1"/>',
        "unknown-shape": '<capsule radius="1" length="1"/>',
        "mesh-no-file": "<mesh/>",
        "mesh-missing-package": '<mesh filename="package://nowhere/m.obj"/>',
        "mesh-package-only": '<mesh filename="package://arm3_description"/>',
        "mesh-file-uri": '<mesh filename="file:///nonexistent/m.stl"/>',
        "mesh-absolute": '<mesh filename="/nonexistent/m.dae"/>',
        "mesh-folder": '<mesh filename="package://arm3_description/meshes"/>',
        "mesh-zero-scale": '<mesh filename="meshes/small_motor.obj" scale="0 0 0"/>',
        "mesh-negative-scale": '<mesh filename="meshes/small_motor.obj" scale="-1 1 1"/>',
        "box-negative": '<box size="-1 1 1"/>',
        "box-huge": '<box size="1e19 1 1"/>',
        "sphere-tiny": '<sphere radius="1e-300"/>',
        "cylinder-nan": '<cylinder radius="nan" length="1"/>',
    }
    for name, shape in bad_visuals.items():
        out[f"visual-{name}"] = robot([link("a", shape)])
        out[f"collision-{name}"] = robot([
            f'<link name="a"><collision><geometry>{shape}</geometry></collision></link>'])
    out["visual-no-geometry"] = robot(['<link name="a"><visual><origin xyz="0 0 0"/></visual></link>'])
    out["origin-extreme"] = robot([link("a"), link("b"), joint(
        "j", "a", "b", origin='<origin xyz="1e19 0 0" rpy="1e300 0 0"/>')])
    out["origin-bad"] = robot([link("a"), link("b"), joint(
        "j", "a", "b", origin='<origin xyz="0 0" rpy="a b c"/>')])
    # The XML reader: prolog, comments, CDATA, references of every form, and its refusals.
    refs = ["&lt;", "&gt;", "&amp;", "&quot;", "&apos;", "&#65;", "&#x41;", "&#X41;", "&#xe9;",
            "&#233;", "&#x20AC;", "&#8364;", "&#x1F600;", "&#128512;", "&#x10FFFF;",
            "&#1114111;", "&#x7FF;", "&#x800;", "&#xFFFF;", "&#x10000;", "&#xAbCdE;",
            "&#00000065;", "&#x0000041;"]
    for i, ref in enumerate(refs):
        out[f"ref-attribute-{i}"] = robot([link(f"a{ref}b")], name=f"r{ref}")
        out[f"ref-text-{i}"] = robot([link("a"), f"<note>x{ref}y</note>"])
    bad_refs = ["&#0;", "&#x110000;", "&#1114112;", "&#;", "&#x;", "&#xG1;", "&#12a;",
                "&#123456789;", "&#x123456789;", "&bogus;", "&;", "& ", "&amp", "&#1;", "&#10;",
                "&#x7F;", "&verylongentityname;"]
    for i, ref in enumerate(bad_refs):
        out[f"badref-attribute-{i}"] = robot([link(f"a{ref}b")])
        out[f"badref-text-{i}"] = robot([link("a"), f"<note>{ref}</note>"])
    prologs = {
        "bom": '\ufeff<?xml version="1.0"?>\n',
        "doctype": '<!DOCTYPE robot>\n',
        "doctype-internal": '<!DOCTYPE robot [ <!ELEMENT robot ANY> ]>\n',
        "comment": "<!-- a comment -->\n<?pi x?>\n",
        "crlf": '<?xml version="1.0"?>\r\n',
        "none": "",
    }
    for name, prolog in prologs.items():
        out[f"prolog-{name}"] = robot(chain(2), prolog=prolog)
    xml_errors = {
        "unterminated-pi": '<?xml version="1.0"\n<robot name="r"/>',
        "unterminated-comment": '<robot name="r"><!-- x </robot>',
        "double-dash": '<robot name="r"><!-- a -- b --></robot>',
        "unterminated-doctype": '<!DOCTYPE robot [ <robot name="r"/>',
        "bang-outside": '<!ELEMENT x>\n<robot name="r"/>',
        "bang-inside": '<robot name="r"><!ELEMENT x></robot>',
        "text-outside": 'x<robot name="r"/>',
        "two-roots": '<robot name="r"/><robot name="s"/>',
        "empty": "",
        "only-comment": "<!-- nothing -->",
        "no-name": "<>",
        "unterminated-tag": '<robot name="r"',
        "no-space": '<robot name="r"name="s"/>',
        "no-value": '<robot name/>',
        "unquoted": '<robot name=r/>',
        "unterminated-value": '<robot name="r/>',
        "lt-in-value": '<robot name="a<b"/>',
        "twice": '<robot name="r" name="s"/>',
        "never-closed": '<robot name="r"><link name="a"/>',
        "mismatch": '<robot name="r"><link name="a"></joint></robot>',
        "close-no-gt": '<robot name="r"></robot',
        "cdata": '<robot name="r"><link name="a"/><x><![CDATA[ <&> ]]></x></robot>',
        "unterminated-cdata": '<robot name="r"><x><![CDATA[ abc </x></robot>',
        "pi-inside": '<robot name="r"><?pi inside?><link name="a"/></robot>',
        "single-quotes": "<robot name='r'><link name='a'/></robot>",
        "spaces-around-equals": '<robot name = "r" ><link name =\t"a" /></robot >',
        "deep": '<robot name="r">' + "<x>" * 300 + "</x>" * 300 + "</robot>",
        "not-robot": '<model name="r"><link name="a"/></model>',
        "utf8-name": '<robot name="r\u00e9"><link name="\u00e9l\u00e8ve"/></robot>',
        "latin1-name": None,
    }
    for name, text in xml_errors.items():
        if text is not None:
            out[f"xml-{name}"] = text
    out["xml-latin1-name"] = b'<robot name="r\xe9"><link name="a"/></robot>'
    return out


def main():
    OUT.mkdir(parents=True, exist_ok=True)
    for old in OUT.glob("gen-*.urdf"):
        old.unlink()
    written = 0
    for name, text in seeds().items():
        data = text if isinstance(text, bytes) else text.encode("utf-8")
        (OUT / f"gen-{name}.urdf").write_bytes(data)
        written += 1
    print(f"{written} seeds in {OUT}")


if __name__ == "__main__":
    main()
