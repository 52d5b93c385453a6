"""A generated table between two marker lines of a README (GPL-2.0-or-later): the studies'
scripts rewrite their own table and leave the prose around it."""
import os


def replace_marked(path, mark, text):
    """Put text between mark[0] and mark[1] in the file at path, each marker on its own line;
    nothing if the file or either marker is missing (a README without a generated table)."""
    if not os.path.isfile(path):
        return
    with open(path) as f:
        s = f.read()
    a, b = s.find(mark[0]), s.find(mark[1])
    if a < 0 or b <= a:
        return
    with open(path, "w") as f:
        f.write(s[:a + len(mark[0])] + "\n" + text.rstrip("\n") + "\n" + s[b:])
