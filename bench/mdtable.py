"""Read numbers back from the markdown tables the report scripts write (for the checks
of ``python -m bench.reports --check``)."""

import re


def section(text, heading):
    """The text under the first heading line containing ``heading``, up to the next
    heading of the same or a higher level."""
    lines = text.splitlines()
    for i, line in enumerate(lines):
        m = re.match(r"(#+) ", line)
        if m and heading in line:
            level = len(m.group(1))
            out = []
            for rest in lines[i + 1:]:
                n = re.match(r"(#+) ", rest)
                if n and len(n.group(1)) <= level:
                    break
                out.append(rest)
            return "\n".join(out)
    raise KeyError("no heading with %r" % heading)


def tables(text):
    """Every markdown table in ``text`` as a list of rows (lists of cell strings), the
    header row first, the separator row left out."""
    out, cur = [], []
    for line in text.splitlines() + [""]:
        if line.startswith("|"):
            cells = [c.strip() for c in line.strip().strip("|").split("|")]
            if not all(re.fullmatch(r":?-+:?", c) for c in cells):
                cur.append(cells)
        elif cur:
            out.append(cur)
            cur = []
    return out


def cell(table, row_label, column):
    """The cell of the row whose first cell is ``row_label`` in the column headed
    ``column``."""
    head = table[0]
    j = head.index(column)
    for row in table[1:]:
        if row[0] == row_label:
            return row[j]
    raise KeyError("no row %r" % row_label)
