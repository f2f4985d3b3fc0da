"""Prints the frames of vantage's cameras.urdf.xacro and static_transforms.launch.py, read with
Python's own XML parser and ast (no ROS needed): one line per frame,
"xacro CHILD PARENT x y z roll pitch yaw" and "launch CHILD PARENT x y z qx qy qz qw"."""
import ast
import math
import sys
import xml.etree.ElementTree as ET

XACRO = '{http://www.ros.org/wiki/xacro}'


def value(text):
    # ${-pi/2}: the only expression the file writes.
    text = text.strip()
    if text.startswith('${') and text.endswith('}'):
        return float(eval(text[2:-1], {'pi': math.pi}))  # noqa: S307 (our own file)
    return float(text)


root = ET.parse(sys.argv[1]).getroot()
macro = root.find(XACRO + 'macro')
for joint in macro.findall('joint'):
    origin = joint.find('origin')
    numbers = [value(v) for v in origin.get('xyz').split()]
    numbers += [value(v) for v in origin.get('rpy').split()]
    print('xacro', joint.find('child').get('link'), joint.find('parent').get('link'),
          ' '.join(repr(n) for n in numbers))

tree = ast.parse(open(sys.argv[2]).read())
for node in ast.walk(tree):
    if isinstance(node, ast.Call) and getattr(node.func, 'id', '') == '_static_transform':
        # _static_transform(node, child, parent, xyz, xyzw)
        name = node.args[1].value
        parent = node.args[2].value if isinstance(node.args[2], ast.Constant) else '$parent'
        numbers = [float(e.value) for e in node.args[3].elts + node.args[4].elts]
        print('launch', name, parent, ' '.join(repr(n) for n in numbers))
