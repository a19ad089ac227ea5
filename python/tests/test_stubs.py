"""The public interface: the type stubs (frix/__init__.pyi) against the package (every public
name, and every public callable's parameters: names, kinds, which have defaults; classes'
public bases, members and fields), and the public names all frix's, wherever defined."""
import ast
import enum
import inspect
import pathlib
import pickle

import frix


def stub_tree():
    return ast.parse(pathlib.Path(frix.__file__).with_suffix(".pyi").read_text())


def test_type_stubs_cover_the_public_names():
    tree = stub_tree()
    names = {n.name for n in tree.body if isinstance(n, (ast.ClassDef, ast.FunctionDef))}
    names |= {t.id for n in tree.body if isinstance(n, ast.AnnAssign) for t in [n.target]}
    assert set(frix.__all__) <= names, set(frix.__all__) - names


def stub_parameters(fn, bound):
    """(name, kind, has a default) of each parameter of a stub's def; without the first for a
    method read from its class bound (a classmethod's cls)."""
    a = fn.args
    positional = a.posonlyargs + a.args
    defaults = [None] * (len(positional) - len(a.defaults)) + list(a.defaults)
    out = [(p.arg, "POSITIONAL_ONLY" if k < len(a.posonlyargs) else "POSITIONAL_OR_KEYWORD",
            d is not None) for k, (p, d) in enumerate(zip(positional, defaults))]
    if a.vararg:
        out.append((a.vararg.arg, "VAR_POSITIONAL", False))
    out += [(p.arg, "KEYWORD_ONLY", d is not None) for p, d in zip(a.kwonlyargs, a.kw_defaults)]
    if a.kwarg:
        out.append((a.kwarg.arg, "VAR_KEYWORD", False))
    return out[1:] if bound else out


def parameters(obj):
    return [(p.name, p.kind.name, p.default is not p.empty)
            for p in inspect.signature(obj).parameters.values()]


def decorators(fn):
    return {ast.unparse(d) for d in fn.decorator_list}


def own_public_names(cls):
    """The public attributes the package defines on cls (not those of Python's own bases)."""
    names = set()
    for base in cls.__mro__:
        if base.__module__.split(".")[0] == "frix":
            names |= {n for n in vars(base) if not n.startswith("_")}
    return names


def class_problems(node, cls):
    problems = []
    where = f"frix.{node.name}"
    stub_bases = [ast.unparse(b).split(".")[-1] for b in node.bases]
    if "NamedTuple" in stub_bases:
        fields = [n.target.id for n in node.body if isinstance(n, ast.AnnAssign)]
        if tuple(fields) != cls._fields:
            problems.append(f"{where}: fields {fields} in the stub, {list(cls._fields)} in the package")
        return problems
    bases = [b.__name__ for b in cls.__bases__ if not b.__name__.startswith("_")]
    if stub_bases != bases:
        problems.append(f"{where}: bases {stub_bases} in the stub, {bases} in the package")
    declared = {n.target.id for n in node.body if isinstance(n, ast.AnnAssign)}
    if issubclass(cls, enum.Enum):
        members = [n.target.id for n in node.body if isinstance(n, ast.AnnAssign)]
        if members != list(cls.__members__):
            problems.append(f"{where}: members {members} in the stub, {list(cls.__members__)} "
                            "in the package")
    target = cls(0, "") if issubclass(cls, frix.Error) else cls  # (Error.code is the instance's)
    problems += [f"{where}.{name}: in the stub, not in the package" for name in sorted(declared)
                 if not hasattr(target, name)]
    for fn in (n for n in node.body if isinstance(n, ast.FunctionDef)):
        declared.add(fn.name)
        member = inspect.getattr_static(cls, fn.name, None)
        if member is None:
            problems.append(f"{where}.{fn.name}: in the stub, not in the package")
        elif "property" in decorators(fn):
            if not isinstance(member, property):
                problems.append(f"{where}.{fn.name}: a property in the stub, not in the package")
        else:
            bound = "classmethod" in decorators(fn)
            if bound != isinstance(member, classmethod):
                problems.append(f"{where}.{fn.name}: classmethod in one only")
            stub, real = stub_parameters(fn, bound), parameters(getattr(cls, fn.name))
            if stub != real:
                problems.append(f"{where}.{fn.name}: {stub} in the stub, {real} in the package")
    problems += [f"{where}.{name}: in the package, not in the stub"
                 for name in sorted(own_public_names(cls) - declared - set(getattr(cls, "__members__", ())))]
    return problems


def test_type_stubs_match_the_signatures():
    problems = []
    for node in stub_tree().body:
        if not isinstance(node, (ast.ClassDef, ast.FunctionDef)) or node.name not in frix.__all__:
            continue
        obj = getattr(frix, node.name)
        if isinstance(node, ast.ClassDef):
            problems += class_problems(node, obj)
        elif stub_parameters(node, False) != parameters(obj):
            problems.append(f"frix.{node.name}: {stub_parameters(node, False)} in the stub, "
                            f"{parameters(obj)} in the package")
    assert not problems, "\n".join(problems)


def test_public_names_are_frixs():
    """Pickles, reprs and tracebacks name frix.Status, frix.DimensionError, not the module that
    defines them, and a pickle of frix's values loads."""
    for name in frix.__all__:
        assert getattr(frix, name).__module__ == "frix", name
    stage = frix.Stage("nsgs", frix.Status.MAX_ITER, 3, 0, 0, 0, False, 0.5, 0.01, "a note")
    for value in (frix.Status.CONVERGED, frix.Existence.DOUBTFUL, stage, frix.solvers()[0]):
        data = pickle.dumps(value)
        assert b"frix.result" not in data and b"frix.options" not in data
        assert pickle.loads(data) == value
    assert str(frix.Status.DIVERGED) == "diverged" and repr(frix.Status(5)) == "<Status.DIVERGED: 5>"
