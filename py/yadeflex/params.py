"""Declared parameters: each option once, with its unit, allowed values, meaning and stage.

A dataclass field declared with `param(default, ...)` carries a `Param` in its metadata. The main
job's command line and --help (module_cli), the checks (`check`, `parse`), the filled module's
cache key (the fields of the fill stage: ModuleParams.fill_key) and the README's option table
(scripts/options_table.py) are read from it, so a new option is declared in one place:

    drop_height: float = param(2.0, unit="m", stage=IMPACT, allowed=C.Range(0.0, 127.0, "m"),
                               meaning="free fall onto the fill top", small=1.0)
"""
import dataclasses

from . import checks as C

FILL, IMPACT, RUN = "fill", "impact", "run"  # stages: the filled module depends on FILL's fields only
KINDS = ("number", "integer", "boolean", "choice", "pair", "flag")
BOOLEAN_WORDS = "/".join(C.TRUE_WORDS[:2] + C.FALSE_WORDS[:2] + ("1", "0"))


@dataclasses.dataclass(frozen=True)
class Param:
    """One option's declaration. allowed: a checks.Range (number), (lo, hi) (integer), the options
    (choice; None among them: unset); default_text: how the default reads where it is not a value
    (None: its value); small: its value in the reduced module (ModuleParams.small); row: the
    option whose line of the README's table this one shares; checker: a function (name, value)
    -> value that checks instead (a refusal with more to say than the values allowed)."""
    kind: str = "number"
    unit: str = ""
    stage: str = FILL
    meaning: str = ""
    allowed: object = None
    default_text: str = None
    small: object = None
    row: str = None
    checker: object = None

    def __post_init__(self):
        if self.kind not in KINDS or self.stage not in (FILL, IMPACT, RUN):
            raise ValueError(f"Param: kind {self.kind!r} (one of {KINDS}), stage {self.stage!r}")
        if (self.kind == "number") != isinstance(self.allowed, C.Range):
            raise ValueError(f"Param: a number takes a checks.Range as allowed (kind {self.kind!r}, allowed {self.allowed!r})")

    def allowed_text(self):
        """The values allowed, as --help and the refusals say them."""
        if self.kind == "number":
            return self.allowed.text()
        if self.kind == "integer":
            return f"a whole number in [{self.allowed[0]}, {self.allowed[1]}]"
        if self.kind == "boolean":
            return BOOLEAN_WORDS
        if self.kind == "choice":
            return "one of " + ", ".join(str(o) for o in self.allowed if o is not None)
        if self.kind == "pair":
            return f"x y [{self.unit}], two finite numbers"
        return "no value (a flag)"

    def check(self, name, v):
        """v converted (float, int, bool, tuple), or checks.BadValue naming `name`. None passes
        where the default is unset (default_text)."""
        if v is None and self.default_text is not None:
            return None
        if self.checker is not None:
            return self.checker(name, v)
        if self.kind == "number":
            return C.number(name, v, self.allowed)
        if self.kind == "integer":
            return C.integer(name, v, *self.allowed)
        if self.kind in ("boolean", "flag"):
            return C.choice(name, v, (True, False))
        if self.kind == "choice":
            return C.choice(name, v, tuple(o for o in self.allowed if o is not None))
        return C.vector(name, v, 2)

    def parse(self, name, text):
        """The value of command-line text (a list of two for a pair), checked, or BadValue."""
        try:
            if self.kind == "number":
                v = float(text)
            elif self.kind == "integer":
                v = int(text)
            elif self.kind in ("boolean", "flag"):
                v = C.boolean(name, text)
            elif self.kind == "choice":
                v = next((o for o in self.allowed if o is not None and str(o) == text), text)
            else:
                v = tuple(float(x) for x in text)
        except (ValueError, TypeError, C.BadValue):
            raise C.BadValue(name, text if self.kind != "pair" else tuple(text), self.allowed_text()) from None
        return self.check(name, v)


def param(default, kind="number", **kw):
    """A dataclass field with default `default` declared by Param(kind, **kw)."""
    return dataclasses.field(default=default, metadata={"param": Param(kind, **kw)})


def declared(cls):
    """{name: (dataclasses.Field, Param)} of the fields of dataclass cls declared with param()."""
    return {f.name: (f, f.metadata["param"]) for f in dataclasses.fields(cls) if "param" in f.metadata}


def default_text(f, p):
    """How field f's default reads (--help, the README)."""
    if p.default_text is not None and f.default is None:
        return p.default_text
    if p.kind in ("boolean", "flag"):
        return str(f.default).lower()
    if p.kind == "pair":
        return " ".join(f"{x:g}" for x in f.default)
    return f"{f.default:g}" if isinstance(f.default, float) else str(f.default)


def help_text(f, p):
    """--help's text of field f: what it means, the values allowed, its default."""
    small = f" (--small: {p.small:g})" if p.small is not None else ""
    return f"{p.meaning}; {p.allowed_text()}; default {default_text(f, p)}{small}".replace("`", "")


def option(name):
    return "--" + name.replace("_", "-")


def table(*classes):
    """The README's option table (markdown lines) of the declared fields of dataclasses classes,
    options sharing a row (Param.row) on one line."""
    rows = {}
    for cls in classes:
        for name, (f, p) in declared(cls).items():
            rows.setdefault(p.row or name, []).append((name, f, p))
    lines = ["| option | default | unit | meaning |", "|---|---|---|---|"]
    for items in rows.values():
        units = [p.unit or "-" for _, _, p in items]
        unit = units[0] if len(set(units)) == 1 else ", ".join(units)
        opts = ", ".join(f"`{option(n)}`" + (" X Y" if p.kind == "pair" else "") for n, _, p in items)
        lines.append(f"| {opts} | {', '.join(default_text(f, p) for _, f, p in items)} | {unit} | {'; '.join(p.meaning for _, _, p in items)} |")
    return lines
