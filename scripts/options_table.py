# The README's table of the main job's options, from their declarations (GPL-2.0-or-later).
#
#     yade-double -n -x scripts/options_table.py           prints the table
#     yade-double -n -x scripts/options_table.py --write   writes it into README.md
#
# tests/yade/test_options.py checks that the README's table is the one written here.
import os
import sys

HERE = next((os.path.dirname(os.path.abspath(a)) for a in sys.argv if a.endswith("options_table.py")), os.getcwd())
sys.path.insert(0, os.path.join(os.path.dirname(HERE), "py"))

from yadeflex.module.cli import readme_table, readme_with_table  # noqa: E402

if "--write" in sys.argv:
    path = os.path.join(os.path.dirname(HERE), "README.md")
    with open(path) as f:
        text = f.read()
    with open(path, "w") as f:
        f.write(readme_with_table(text))
    print(f"wrote the option table into {path}")
else:
    print("\n".join(readme_table()))
