"""Reading a node tree for constants: the value of an input, followed through what can be folded,
and a report naming the material and the node where a value cannot be (procedural textures): the
input's own constant is then taken, the nearest constant the node tree holds."""


def active_output(tree, kind):
    """The active output node of a kind ('OUTPUT_MATERIAL', 'OUTPUT_WORLD') that Cycles would use."""
    outputs = [n for n in tree.nodes if n.type == kind and getattr(n, "target", "ALL") in ("ALL", "CYCLES")]
    for n in outputs:
        if n.is_active_output:
            return n
    return outputs[0] if outputs else None


def linked_node(socket):
    """The node feeding a socket (through reroutes), or None."""
    if not socket.is_linked:
        return None
    link = socket.links[0]
    if not link.is_valid or link.is_muted:
        return None
    node = link.from_node
    while node.type == "REROUTE":
        if not node.inputs[0].is_linked:
            return None
        node = node.inputs[0].links[0].from_node
    return node


def find_input(node, *names):
    """The first input with one of the names (Blender 3.x and 4.x names differ), or None."""
    for n in names:
        s = node.inputs.get(n)
        if s is not None:
            return s
    return None


def constant(socket, owner, reports, what="value"):
    """A socket's value: its own when unlinked, a Value or RGB node's output when linked to one,
    otherwise its default with a report naming the node it is linked to."""
    if socket is None:
        return None
    node = linked_node(socket)
    if node is None:
        v = socket.default_value
    elif node.type == "RGB":
        v = node.outputs[0].default_value
    elif node.type == "VALUE":
        v = node.outputs[0].default_value
    else:
        reports.warn(f"{owner}: node '{node.name}' ({node.bl_label}) feeding {socket.name} is not translated; "
                     f"rendered with the input's own {what}")
        v = socket.default_value
    try:
        return [float(c) for c in v][:3]
    except TypeError:
        return float(v)
