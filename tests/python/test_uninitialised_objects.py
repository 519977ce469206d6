"""Issue 45: objects made by Cls.__new__(Cls) alone, as self and as arguments, and objects
initialised twice. The module is introspected, so that a class, method or function added later
is covered without a word here: every class, every function and method (their pybind11
signatures), every property and every keyword of the option tables is called with an
uninitialised object of every class in each place that takes an object. Each call runs in a
forked child, so that a crash or a hang is reported as a failure instead of ending pytest."""
import inspect
import os
import re
import select
import signal
import time

import numpy as np
import pytest

import mdbrief
from conftest import FISHEYE_CAMERA, PINHOLE_CAMERA, SOURCE

MODULE = mdbrief._mdbrief
# A set: TestSet is ComparisonSet under its old name, one class.
CLASSES = sorted({c for _, c in inspect.getmembers(MODULE, inspect.isclass) if c.__module__ == MODULE.__name__},
                 key=lambda c: c.__name__)
VOCABULARY = SOURCE / "configs/vocabularies/tracking_k10_L4.mdbvoc"
# The option table behind each **kwargs (mdbrief.option_fields), or the camera's parameters.
KEYWORD_TABLES = {"MdBrief.__init__": "MdBrief", "match": "match", "match_guided": "match_guided",
                  "fit_essential": "two_view", "fit_homography": "two_view", "check_known_pose": "two_view",
                  "train": "train", "refine_matches": "refine_matches"}


def uninitialised(cls):
    return cls.__new__(cls)


def live(cls):
    """An initialised object of each class."""
    camera = mdbrief.load_camera(str(PINHOLE_CAMERA))
    rng = np.random.default_rng(1)
    bearings = rng.normal(size=(20, 3))
    make = {
        "Camera": lambda: camera,
        "CameraRig": lambda: mdbrief.load_rig(str(FISHEYE_CAMERA)),
        "Database": lambda: mdbrief.Database(mdbrief.Vocabulary.load(str(VOCABULARY))),
        "MdBrief": lambda: mdbrief.MdBrief(camera),
        "RefinedMatches": lambda: mdbrief.refine_matches(mdbrief.MdBrief(camera), SAMPLES["image_a"](), [],
                                                         SAMPLES["image_b"](), [], []),
        "ComparisonSet": lambda: mdbrief.load_pattern(mdbrief.default_pattern()),
        "TwoViewResult": lambda: mdbrief.fit_essential(bearings, bearings),
        "Vocabulary": lambda: mdbrief.Vocabulary.load(str(VOCABULARY)),
    }
    return make[cls.__name__]()


def test_every_class_has_a_live_object_here():
    """A new class needs a line in live(); this names it."""
    assert len(CLASSES) >= 7
    for cls in CLASSES:
        assert isinstance(live(cls), cls)


class Parameter:
    def __init__(self, text):
        text = text.split("=")[0].strip()
        self.star = text.startswith("*")
        self.name, _, self.type = (part.strip() for part in text.lstrip("*").partition(":"))


def top_level_split(text):
    parts, depth, start = [], 0, 0
    for i, ch in enumerate(text):
        depth += ch in "[(" and 1 or ch in "])" and -1 or 0
        if ch == "," and depth == 0:
            parts.append(text[start:i])
            start = i + 1
    parts.append(text[start:])
    return [p.strip() for p in parts if p.strip()]


def signatures(function):
    """The parameters of each overload, from pybind11's docstring: [(positional, keyword-only)]."""
    found = []
    lines = (function.__doc__ or "").splitlines()
    # One signature on the first line, or "Overloaded function." and then numbered ones.
    if lines[:1] == ["Overloaded function."]:
        lines = [line for line in lines if re.match(r"^\d+\. ", line)]
    else:
        lines = lines[:1]
    for line in lines:
        match = re.match(r"^(?:\d+\. )?[\w.]*\((.*)\) -> ", line)
        if not match:
            continue
        positional, keyword_only, after_star = [], [], False
        for text in top_level_split(match.group(1)):
            if text == "*":
                after_star = True
                continue
            p = Parameter(text)
            if not p.star:
                (keyword_only if after_star else positional).append(p)
        found.append((positional, keyword_only))
    return found


def callables():
    """(name, function, class or None, takes self) for every function, method and property getter."""
    out = []
    for name, f in inspect.getmembers(MODULE, inspect.isbuiltin):
        out.append((name, f, None, False))
    for cls in CLASSES:
        for name, attribute in vars(cls).items():
            qualified = f"{cls.__name__}.{name}"
            if isinstance(attribute, property):
                out.append((qualified, attribute.fget, cls, True))
            elif isinstance(attribute, staticmethod):
                out.append((qualified, getattr(cls, name), cls, False))
            elif callable(attribute) and signatures(getattr(cls, name)):
                out.append((qualified, getattr(cls, name), cls, True))
    return out


CALLABLES = callables()


def test_the_module_is_enumerated():
    names = {name for name, *_ in CALLABLES}
    for expected in ["pixels_per_radian", "Camera.pixel_to_bearing", "Camera.__init__", "Camera.__setstate__",
                     "CameraRig.ids", "CameraRig.relative_pose", "CameraRig.__len__", "Database.__init__",
                     "Database.load", "MdBrief.__init__", "ComparisonSet.first", "load_pattern", "train"]:
        assert expected in names, expected
    for _, function, _, _ in CALLABLES:
        assert signatures(function), function.__doc__


# Values that the functions take for their untyped (handle) parameters, by name, so that the
# object fed in another place is reached. A parameter missing here gets None, and a call that
# then fails on it instead of on the object fed names neither: the test says which.
SAMPLES = {
    "d1": lambda: np.zeros((2, 32), np.uint8), "d2": lambda: np.zeros((2, 32), np.uint8),
    "masks1": lambda: np.zeros((2, 32), np.uint8), "masks2": lambda: np.zeros((2, 32), np.uint8),
    "descriptors": lambda: np.zeros((2, 32), np.uint8), "bow": dict, "keypoints": list, "keypoints2": list,
    "predicted": lambda: np.zeros((2, 2)), "pixels": lambda: np.array([[1.0, 2.0]]),
    "bearings": lambda: np.array([[0.0, 0.0, 1.0]]),
    "bearings_a": lambda: np.random.default_rng(1).normal(size=(10, 3)),
    "bearings_b": lambda: np.random.default_rng(2).normal(size=(10, 3)),
    "rotation": lambda: np.eye(3), "translation": lambda: np.array([1.0, 0.0, 0.0]),
    "image": lambda: np.zeros(live(mdbrief.Camera).image_size[::-1], np.uint8),
    "image_a": lambda: np.zeros(live(mdbrief.Camera).image_size[::-1], np.uint8),
    "image_b": lambda: np.zeros(live(mdbrief.Camera).image_size[::-1], np.uint8),
    "keypoints_a": list, "keypoints_b": list, "matches": list,
    "tests": lambda: [[0, 0, 0, 0]], "K": lambda: np.eye(3), "D": lambda: np.zeros(4),
    "path": lambda: "/nonexistent/mdbrief-sample", "which": lambda: 0, "i": lambda: 0, "j": lambda: 0,
}


def placeholder(parameter):
    """A value of the parameter's type that the call accepts (when no other argument is refused)."""
    kinds = {"int": 1, "float": 1.0, "str": "x", "bool": False, "Tuple[int, int]": (1, 1), "List[str]": [],
             "tuple": (), "dict": {}}
    for cls in CLASSES:
        if parameter.type.endswith("." + cls.__name__):
            return live(cls)
    if parameter.type in ("handle", "object"):
        return SAMPLES.get(parameter.name, lambda: None)()
    return kinds[parameter.type]


def run_in_child(call, timeout=60):
    """What call() does in a forked child: 'returned', 'Type: message', 'signal N' or 'hang'."""
    read, write = os.pipe()
    pid = os.fork()
    if pid == 0:
        os.close(read)
        try:
            call()
            text = "returned"
        except BaseException as e:  # noqa: BLE001 (reported to the parent, which judges)
            text = f"{type(e).__name__}: {e}"
        os.write(write, text.encode("utf-8", "backslashreplace")[:60000])
        os._exit(0)
    os.close(write)
    deadline, chunks = time.monotonic() + timeout, []
    with os.fdopen(read, "rb") as pipe:
        while time.monotonic() < deadline:
            if select.select([pipe], [], [], max(0.0, deadline - time.monotonic()))[0]:
                chunk = os.read(pipe.fileno(), 65536)
                if not chunk:
                    break
                chunks.append(chunk)
        else:
            os.kill(pid, signal.SIGKILL)
            os.waitpid(pid, 0)
            return "hang"
    _, status = os.waitpid(pid, 0)
    if os.WIFSIGNALED(status):
        return f"signal {os.WTERMSIG(status)}"
    return b"".join(chunks).decode()


def clean_refusal(outcome, cls, argument):
    """TypeError or ValueError that says the object of `cls` was never initialised, or that names
    the argument it came as (a path, an array, a number expected there)."""
    kind, _, message = outcome.partition(": ")
    if kind not in ("TypeError", "ValueError"):
        return False
    if "never initialised" in message:
        return f"mdbrief.{cls.__name__} " in message
    return re.search(rf"\b{re.escape(argument)}\b", message) is not None


def cases(name, function, owner, takes_self):
    """(description, call, class fed, argument name) for every place of every overload."""
    out = []
    for positional, keyword_only in signatures(function):
        first = 1 if takes_self else 0
        args = [placeholder(p) for p in positional[first:]]
        self_class = owner if takes_self else None
        constructs = name.endswith(("__init__", "__setstate__"))

        def self_object():
            return uninitialised(owner) if constructs else live(owner)

        if takes_self and not constructs:
            out.append((f"{name}(self=uninitialised)",
                        lambda a=args: function(uninitialised(owner), *a), owner, "self"))
        places = [(i, p.name) for i, p in enumerate(positional[first:])]
        places += [(p.name, p.name) for p in keyword_only]
        table = KEYWORD_TABLES.get(name)
        keywords = [f["keyword"] for f in mdbrief.option_fields(table)] if table else []
        if name == "Camera.__init__":
            keywords = sorted({k for ks in mdbrief.camera_models().values() for k in ks})
        places += [(k, k) for k in keywords]
        for place, argument in places:
            declared = positional[first + place].type if isinstance(place, int) else None
            fed = [c for c in CLASSES if declared is None or declared in ("handle", "object")
                   or declared.endswith("." + c.__name__)]
            for cls in fed:
                def call(place=place, cls=cls):
                    a, k = list(args), {}
                    if isinstance(place, int):
                        a[place] = uninitialised(cls)
                    else:
                        k[place] = uninitialised(cls)
                    return function(*([self_object()] if self_class else []), *a, **k)
                out.append((f"{name}({argument}=uninitialised {cls.__name__})", call, cls, argument))
    return out


@pytest.mark.parametrize("name, function, owner, takes_self", CALLABLES, ids=[c[0] for c in CALLABLES])
def test_uninitialised_objects_are_refused_as_self_and_as_every_argument(name, function, owner, takes_self):
    """Issue 45: CameraRig.__new__(CameraRig).ids crashed; pixels_per_radian(Camera.__new__(Camera), ...),
    Database(Vocabulary.__new__(Vocabulary)) and MdBrief(camera, pattern=ComparisonSet.__new__(ComparisonSet))
    crashed or read garbage."""
    failures = []
    for description, call, cls, argument in cases(name, function, owner, takes_self):
        outcome = run_in_child(call)
        if not clean_refusal(outcome, cls, argument):
            failures.append(f"{description}: {outcome[:300]}")
    assert not failures, "\n".join(failures)


def test_the_issue_cases_name_the_class():
    cases = [
        (lambda: uninitialised(mdbrief.CameraRig).ids, "CameraRig"),
        (lambda: uninitialised(mdbrief.CameraRig).relative_pose(0, 1), "CameraRig"),
        (lambda: len(uninitialised(mdbrief.CameraRig)), "CameraRig"),
        (lambda: mdbrief.pixels_per_radian(uninitialised(mdbrief.Camera), [[1.0, 2.0]]), "Camera"),
        (lambda: mdbrief.Camera.pixel_to_bearing(uninitialised(mdbrief.Camera), [[1.0, 2.0]]), "Camera"),
        (lambda: mdbrief.Database(uninitialised(mdbrief.Vocabulary)), "Vocabulary"),
        (lambda: mdbrief.MdBrief(live(mdbrief.Camera), pattern=uninitialised(mdbrief.ComparisonSet)), "ComparisonSet"),
        (lambda: mdbrief.MdBrief(uninitialised(mdbrief.Camera)), "Camera"),
    ]
    for call, name in cases:
        assert run_in_child(call) == (f"TypeError: this mdbrief.{name} object was never initialised (made with "
                                      f"__new__ alone): " + CREATE[name])


CREATE = {"Camera": "create it with mdbrief.Camera(...)", "ComparisonSet": "create it with mdbrief.ComparisonSet(...)",
          "CameraRig": "mdbrief.CameraRig objects come from the module's functions, see help(mdbrief.CameraRig)",
          "Vocabulary": "mdbrief.Vocabulary objects come from the module's functions, see help(mdbrief.Vocabulary)"}


def constructors(cls):
    """The class's own __init__ and __setstate__: a class without a constructor has Python's slot
    wrapper (object.__init__'s type) instead."""
    return [m for m in ("__init__", "__setstate__")
            if m in vars(cls) and not isinstance(vars(cls)[m], type(object.__init__))]


# Only the classes that have a constructor to call again (not a skip per class without one: a
# skip fails under MDBRIEF_NO_SKIPS).
CONSTRUCTED = [c for c in CLASSES if constructors(c)]


@pytest.mark.parametrize("cls", CONSTRUCTED, ids=[c.__name__ for c in CONSTRUCTED])
def test_initialising_a_live_object_again_is_refused(cls):
    """Issue 45: Camera.__init__ on a live camera was ignored without a word (and __setstate__ when
    called through the class)."""
    for method in constructors(cls):
        obj = live(cls)
        before = repr(obj)
        state = obj.__getstate__() if method == "__setstate__" else None
        for call in (lambda: getattr(obj, method), lambda: getattr(cls, method).__get__(obj)):
            with pytest.raises(TypeError, match=rf"^mdbrief\.{cls.__name__}\.{method}: this object is already "
                                                rf"initialised; create a new one"):
                args = (state,) if state is not None else live_arguments(cls)
                call()(*args)
        assert repr(obj) == before


def live_arguments(cls):
    return {"Camera": ("pinhole", 10, 10), "Database": (live(mdbrief.Vocabulary),),
            "MdBrief": (live(mdbrief.Camera),), "ComparisonSet": ("t", [[0, 0, 0, 0]])}[cls.__name__]
