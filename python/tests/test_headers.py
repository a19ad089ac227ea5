"""The package against the C headers (include/frix/*.h, libfrix's: not frix_mpi*.h), as text:
every enumerator is in frix/_constants.py under its C name with its value, and every
function _lib.py declares has the header's prototype (argument count, and each argument's
and the result's kind). CTest runs them as python_constants_match_headers and
python_prototypes_match_headers; the Fortran module has its own (fortran_binding_complete).
"""
import ctypes
import os
import pathlib
import re

from frix import _constants, _lib

INCLUDE = pathlib.Path(os.environ.get("FRIX_INCLUDE_DIR",
                                      pathlib.Path(__file__).parents[2] / "include" / "frix"))


def header_text():
    """The public headers of libfrix, without their comments."""
    paths = sorted(p for p in INCLUDE.glob("*.h") if not p.name.startswith("frix_mpi"))
    assert paths, f"no headers in {INCLUDE}"
    text = "\n".join(p.read_text() for p in paths)
    return re.sub(r"/\*.*?\*/|//[^\n]*", " ", text, flags=re.S)


def enumerators(text):
    """{name: value} of every enumerator, implicit values (previous + 1) included."""
    out = {}
    for body in re.findall(r"\benum\b[^{;]*\{([^}]*)\}", text):
        value = -1
        for item in filter(None, (s.strip() for s in body.split(","))):
            m = re.fullmatch(r"(FRIX_\w+)\s*(?:=\s*(-?\d+))?", item)
            assert m, f"enumerator not understood: {item!r}"
            value = int(m.group(2)) if m.group(2) is not None else value + 1
            out[m.group(1)] = value
    return out


def enum_types(text):
    return set(re.findall(r"\btypedef\s+enum\b[^{;]*\{[^}]*\}\s*(frix_\w+)\s*;", text))


def kind_of_c(ctype, enums, fn_types):
    """The kind of a C type: 'void', 'int', 'int64', 'double', 'char*', 'double*', 'int64*',
    'int*', 'handle' (void * or a pointer to an opaque struct), 'handle*', or ('fn', result,
    args)."""
    t = re.sub(r"\bconst\b", " ", ctype)
    stars = t.count("*")
    base = t.replace("*", " ").split()
    assert len(base) == 1, f"type not understood: {ctype!r}"
    base = base[0]
    if base in fn_types:
        assert stars == 0, ctype
        return fn_types[base]
    scalar = {"void": "void", "int": "int", "int64_t": "int64", "double": "double"}.get(base)
    if base in enums:
        scalar = "int"  # (an enum is int-sized in C: FRIX_ENUM_BASE)
    if stars == 0:
        assert scalar, f"type not understood: {ctype!r}"
        return scalar
    if base == "char" and stars == 1:
        return "char*"
    if scalar in ("double", "int64", "int") and stars == 1:
        return scalar + "*"
    if base == "void" or (scalar is None and base.startswith("frix_")):  # an untyped or opaque pointer
        return "handle" + "*" * (stars - 1)
    raise AssertionError(f"type not understood: {ctype!r}")


def parameter_type(decl):
    """A parameter's type: its declaration without the parameter's name, where it has one."""
    words = [w for w in re.findall(r"\w+", decl) if w != "const"]
    return re.sub(r"\w+\s*$", "", decl.strip()) if len(words) >= 2 else decl


def parameters(args, enums, fn_types):
    args = args.strip()
    if args in ("", "void"):
        return []
    return [kind_of_c(parameter_type(a), enums, fn_types) for a in args.split(",")]


def prototypes(text):
    """{name: (result kind, [argument kinds])} of every FRIX_API function."""
    enums = enum_types(text)
    fn_types = {}
    for ret, name, args in re.findall(r"typedef\s+([\w\s*]+?)\s*\(\s*\*\s*(\w+)\s*\)\s*\(([^)]*)\)\s*;",
                                      text):
        fn_types[name] = ("fn", kind_of_c(ret, enums, {}), tuple(parameters(args, enums, {})))
    out = {}
    for ret, name, args in re.findall(r"FRIX_API\s+([\w\s*]+?)\s*\b(frix_\w+)\s*\(([^)]*)\)\s*;", text):
        out[name] = (kind_of_c(ret, enums, fn_types), parameters(args, enums, fn_types))
    return out


def kind_of_ctypes(t):
    """The kind of a ctypes type, in kind_of_c's terms ('address' for c_void_p)."""
    if t is None:
        return "void"
    if hasattr(t, "_argtypes_"):  # a CFUNCTYPE
        return ("fn", kind_of_ctypes(t._restype_), tuple(kind_of_ctypes(a) for a in t._argtypes_))
    simple = {ctypes.c_int: "int", ctypes.c_int64: "int64", ctypes.c_double: "double",
              ctypes.c_char_p: "char*", ctypes.c_void_p: "address"}
    if t in simple:
        return simple[t]
    pointee = getattr(t, "_type_", None)
    if isinstance(pointee, type) and pointee in simple:
        return {"address": "handle*"}.get(simple[pointee], simple[pointee] + "*")
    raise AssertionError(f"ctypes type not understood: {t!r}")


def matches(c_kind, py_kind):
    """c_void_p (an address) stands for any pointer but a string; the rest must be equal."""
    if py_kind == "address":
        return c_kind == "handle" or (isinstance(c_kind, str) and c_kind.endswith("*")
                                      and c_kind != "char*")
    if isinstance(c_kind, tuple) and isinstance(py_kind, tuple):
        return (matches(c_kind[1], py_kind[1]) and len(c_kind[2]) == len(py_kind[2])
                and all(matches(c, p) for c, p in zip(c_kind[2], py_kind[2])))
    return c_kind == py_kind


def test_constants_match_headers():
    in_headers = enumerators(header_text())
    assert len(in_headers) >= 100, f"only {len(in_headers)} enumerators found in {INCLUDE}"
    in_python = {k: v for k, v in vars(_constants).items() if k.startswith("FRIX_")}
    problems = [f"{k} = {v} is missing from _constants.py" for k, v in in_headers.items()
                if k not in in_python]
    problems += [f"{k} is {in_python[k]} in _constants.py, {v} in the headers"
                 for k, v in in_headers.items() if k in in_python and in_python[k] != v]
    problems += [f"{k} is in _constants.py, not in the headers" for k in in_python
                 if k not in in_headers]
    assert not problems, "\n".join(problems)


def test_prototypes_match_headers():
    in_headers = prototypes(header_text())
    assert len(in_headers) >= 80, f"only {len(in_headers)} prototypes found in {INCLUDE}"
    assert len(_lib.DECLARED) >= 50
    problems = []
    for name in _lib.DECLARED:
        if name not in in_headers:
            problems.append(f"{name} is declared in _lib.py, not in the headers")
            continue
        c_result, c_args = in_headers[name]
        fn = getattr(_lib.lib, name)
        py_result, py_args = kind_of_ctypes(fn.restype), [kind_of_ctypes(a) for a in fn.argtypes]
        if len(py_args) != len(c_args):
            problems.append(f"{name}: {len(py_args)} arguments in _lib.py, {len(c_args)} in C")
        problems += [f"{name}: argument {k + 1} is {p} in _lib.py, {c} in C"
                     for k, (c, p) in enumerate(zip(c_args, py_args)) if not matches(c, p)]
        if not matches(c_result, py_result):
            problems.append(f"{name}: returns {py_result} in _lib.py, {c_result} in C")
    assert not problems, "\n".join(problems)

