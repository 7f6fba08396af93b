"""A configuration read by attribute: ``cfg.simulation.dt_s``, ``cfg.string.sections[0].length_m``.

:class:`Configuration` wraps the normalized configuration dict (:func:`drillpy.model.config.load_config`)
and is what the package's modules read: one block per attribute, one key per attribute of a block,
every name checked against the configuration's JSON Schema (``config.schema.json``, generated from the
engine's parser), so that a typo raises ``AttributeError`` naming the key instead of a ``KeyError``
deep inside a study. It is immutable: :meth:`Configuration.replace` and
:meth:`Configuration.with_overrides` return a new one. The dict stays the form at the JSON edge
(files, results, the engine): :meth:`Configuration.to_dict`, :meth:`Configuration.from_dict`,
:meth:`Configuration.to_json` and :meth:`Configuration.engine` cross it.

    >>> cfg = Configuration.load(preset="thesis-field")
    >>> cfg.simulation.dt_s, cfg.law.type, cfg.string.sections[1].name
    (0.000512, 'hysteretic', 'BHA')
    >>> cfg.replace({"simulation.duration_s": 20.0}).simulation.duration_s
    20.0
"""
from __future__ import annotations

import functools
import json
from pathlib import Path

from drillpy.model import config as _config

__all__ = ["Block", "Configuration"]

SCHEMA_FILE = Path(__file__).with_name("config.schema.json")

_MISSING = object()


@functools.lru_cache(maxsize=None)
def _schema() -> dict:
    """The configuration's JSON Schema (read once)."""
    return json.loads(SCHEMA_FILE.read_text(encoding="utf-8"))


def _definition(name: str | None) -> dict:
    """The schema of a block: the top level for ``None``, else ``$defs[name]``."""
    return _schema() if name is None else _schema()["$defs"][name]


def _ref(prop) -> str | None:
    """The ``$defs`` name a property refers to (``"#/$defs/law"`` -> ``"law"``), or None."""
    ref = prop.get("$ref") if isinstance(prop, dict) else None
    return ref.rsplit("/", 1)[-1] if ref else None


@functools.lru_cache(maxsize=None)
def _keys(name: str | None, kind=_MISSING) -> dict:
    """Key -> property schema of a block.

    ``kind`` is the block's ``type``: the keys of that variant only (the ``if type = ...`` branches of
    the schema's ``allOf``); without it, the keys of every variant (the names a block can ever have).
    """
    node = _definition(name)
    keys = dict(node.get("properties", {}))
    for branch in node.get("allOf", []):
        const = branch.get("if", {}).get("properties", {}).get("type", {}).get("const")
        if kind is not _MISSING and const != kind:
            continue
        for key, prop in branch.get("then", {}).get("properties", {}).items():
            if prop is not True or key not in keys:
                keys[key] = prop
    return keys


def _copy(x):
    """A copy of a JSON value (dicts and lists copied, tuples made lists, views made dicts)."""
    if isinstance(x, Block):
        return x.to_dict()
    if isinstance(x, dict):
        return {k: _copy(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_copy(v) for v in x]
    return x


def _freeze(x):
    """A read-only copy of a JSON value without a schema block: lists become tuples."""
    if isinstance(x, dict):
        return {k: _freeze(v) for k, v in x.items()}
    if isinstance(x, list):
        return tuple(_freeze(v) for v in x)
    return x


def _view(value, prop, path: str):
    """What an attribute gives: a :class:`Block` for an object of the schema, a tuple for an array
    (of blocks, when its items are objects), the value itself for a number or a string."""
    name = _ref(prop)
    if name is not None and isinstance(value, dict):
        return Block(value, name, path)
    if isinstance(value, list):
        item = _ref(prop.get("items")) if isinstance(prop, dict) else None
        if item is not None:
            return tuple(Block(v, item, f"{path}[{i}]") if isinstance(v, dict) else _freeze(v)
                         for i, v in enumerate(value))
        return _freeze(value)
    return _freeze(value)


class Block:
    """A read-only view of one block of a configuration (``cfg.law``, ``cfg.string.sections[0]``).

    Its attributes are the block's keys (``cfg.law.beta1``); a name the schema does not have for the
    block raises ``AttributeError`` naming it, and so does a key the block's ``type`` does not have or
    that is not set (:meth:`get` gives a default for those two instead). A key absent from the dict but
    with a default in the schema gives that default (what the engine uses).

    Parameters
    ----------
    data : dict
        The block (kept, not copied: :class:`Configuration` owns the data).
    schema : str or None
        The block's name in the schema's ``$defs`` (``"law"``, ``"string.sections"``); None for the
        top level.
    path : str
        Where the block is, for messages (``"law"``, ``"string.sections[1]"``).
    """

    __slots__ = ("_data", "_schema_name", "_path")

    def __init__(self, data: dict, schema: str | None, path: str):
        object.__setattr__(self, "_data", data)
        object.__setattr__(self, "_schema_name", schema)
        object.__setattr__(self, "_path", path)

    def _known(self) -> dict:
        """The keys this block may have, given its ``type`` (if it has one)."""
        kind = self._data.get("type", _MISSING)
        return _keys(self._schema_name, kind if isinstance(kind, str) else _MISSING)

    def _prefix(self, name: str) -> str:
        return name if self._path == "config" else f"{self._path}.{name}"

    def get(self, name: str, default=None):
        """The value of a key, or ``default`` when the block does not set it.

        Parameters
        ----------
        name : str
            A key of the block (checked against the schema).
        default : object, optional
            What an unset key gives (None), or a key of another ``type`` of the block (``law.beta1`` of a
            ``tucker_wang`` law); a key with a schema default gives that default.

        Returns
        -------
        object
            A :class:`Block`, a tuple (an array), a number, a string or ``default``.

        Raises
        ------
        AttributeError
            For a name the block cannot have (``"law.bta1: no such key ..."``).
        """
        known, every = self._known(), _keys(self._schema_name)
        if name not in every:
            where = self._path if self._path != "config" else "a configuration"
            raise AttributeError(f"{self._prefix(name)}: no such key (the keys of {where}: "
                                 f"{', '.join(sorted(every))})")
        if name not in known:
            return default
        prop = known[name]
        if name in self._data:
            return _view(self._data[name], prop, self._prefix(name))
        if isinstance(prop, dict) and "default" in prop:
            return _view(_copy(prop["default"]), prop, self._prefix(name))
        return default

    def __getattr__(self, name: str):
        if name.startswith("__"):
            raise AttributeError(name)
        value = self.get(name, _MISSING)
        if value is _MISSING:
            known = self._known()
            if name not in known:
                raise AttributeError(f"{self._prefix(name)}: not a key of {self._path}.type = "
                                     f"{self._data.get('type')!r} (its keys: {', '.join(sorted(known))})")
            raise AttributeError(f"{self._prefix(name)}: not set in this configuration")
        return value

    def __setattr__(self, name, value):
        raise AttributeError(f"{self._prefix(name)}: a configuration is read-only (Configuration.replace gives "
                             "a changed copy)")

    def __contains__(self, name: str) -> bool:
        """Whether the block sets ``name`` (``"law" in cfg``)."""
        return name in self._data

    def keys(self) -> list:
        """The keys the block sets, in order."""
        return list(self._data)

    def to_dict(self) -> dict:
        """A copy of the block as a dict (what the JSON has).

        Returns
        -------
        dict
            The block's keys and values, lists as lists.
        """
        return _copy(self._data)

    def __eq__(self, other) -> bool:
        if isinstance(other, Block):
            return self._data == other._data
        return NotImplemented

    def __reduce__(self):
        return (Block, (self._data, self._schema_name, self._path))

    __hash__ = None

    def __dir__(self):
        return sorted(set(self._known()) | set(object.__dir__(self)))

    def __repr__(self) -> str:
        return f"{type(self).__name__}({self._path}: {json.dumps(self._data)[:200]})"


def _checked_path(path: str) -> list:
    """The keys of a dotted path (``"simulation.dt_s"``), each checked against the schema.

    Raises
    ------
    AttributeError
        Naming the path for a key no block of the schema has.
    """
    keys, schema = path.split("."), None
    for i, key in enumerate(keys):
        known = _keys(schema)
        if key not in known:
            where = ".".join(keys[:i]) or "a configuration"
            raise AttributeError(f"{path}: no such key (the keys of {where}: {', '.join(sorted(known))})")
        schema = _ref(known[key])
        if schema is None and i < len(keys) - 1:
            raise AttributeError(f"{path}: {'.'.join(keys[:i + 1])} is not a block")
    return keys


class Configuration(Block):
    """A configuration read by attribute and changed by copy.

    Parameters
    ----------
    data : dict
        The configuration dict, usually normalized (:func:`drillpy.model.config.load_config`); copied,
        not validated (:meth:`from_dict` validates and normalizes, :meth:`engine` validates).

    Examples
    --------
    >>> cfg = Configuration.load(preset="thesis-field")
    >>> cfg.operation.wob_n
    245000.0
    >>> cfg.simulation.dt_ms
    Traceback (most recent call last):
    ...
    AttributeError: simulation.dt_ms: no such key (the keys of simulation: acceleration, dt_s, ...)
    """

    __slots__ = ()

    def __init__(self, data: dict):
        if not isinstance(data, dict):
            raise TypeError(f"config = {type(data).__name__}: a configuration is a dict (or a Configuration)")
        super().__init__(_copy(data), None, "config")

    @classmethod
    def _owning(cls, data: dict) -> Configuration:
        """A configuration that takes ``data`` as its own (a fresh dict nobody else holds: no copy)."""
        self = cls.__new__(cls)
        Block.__init__(self, data, None, "config")
        return self

    @classmethod
    def of(cls, config) -> Configuration:
        """The configuration a function was given, at its entry: a :class:`Configuration` as is, a dict
        wrapped (copied, not normalized), an engine ``_core.Config`` by its normalized dict.

        Parameters
        ----------
        config : Configuration, dict or _core.Config
            What the caller passed.

        Returns
        -------
        Configuration
        """
        if isinstance(config, Configuration):
            return config
        if isinstance(config, dict):
            return cls(config)
        if hasattr(config, "to_dict"):
            return cls(config.to_dict())
        raise TypeError(f"config = {type(config).__name__}: a configuration is a dict (or a Configuration)")

    @classmethod
    def from_dict(cls, data: dict) -> Configuration:
        """A configuration validated and normalized by the engine (every default explicit).

        Parameters
        ----------
        data : dict
            A configuration, possibly partial.

        Returns
        -------
        Configuration
            ``to_dict()`` gives :func:`drillpy.model.config.normalize` (data).

        Raises
        ------
        ValueError
            Naming the field and the value when the configuration is invalid.
        """
        return cls._owning(_config.normalize(data))

    @classmethod
    def from_json(cls, text: str) -> Configuration:
        """A configuration of JSON text, validated and normalized (the inverse of :meth:`to_json`).

        Parameters
        ----------
        text : str
            JSON text of a configuration.

        Returns
        -------
        Configuration
        """
        return cls.from_dict(json.loads(text))

    @classmethod
    def load(cls, preset: str | None = None, path: str | Path | None = None,
             config: dict | None = None) -> Configuration:
        """A configuration from exactly one of a preset name, a JSON file or a dict
        (:func:`drillpy.model.config.load_config`, normalized).

        Parameters
        ----------
        preset : str, optional
            A built-in preset (:func:`drillpy.model.config.preset_names`).
        path : str or Path, optional
            A JSON configuration file.
        config : dict, optional
            A configuration dict.

        Returns
        -------
        Configuration
        """
        return cls._owning(_config.load_config(preset=preset, path=path, config=config))

    def to_dict(self) -> dict:
        """The configuration as a dict (a copy): what files and results hold.

        Returns
        -------
        dict
            Equal to the dict it was made of (the normalized dict for :meth:`load`).
        """
        return _copy(self._data)

    def to_json(self, indent: int | None = None) -> str:
        """JSON text of the configuration (non-finite numbers refused, as the engine's JSON).

        Parameters
        ----------
        indent : int or None
            Indentation; None (default) for the compact text the engine reads.

        Returns
        -------
        str
        """
        if indent is None:
            return _config.to_json_text(self._data)
        return json.dumps(self._data, indent=indent, allow_nan=False)

    def engine(self):
        """The engine's parsed and validated configuration (:func:`drillpy.model.config.engine_config`:
        plausibility warnings, then ``_core.Config``).

        Returns
        -------
        _core.Config

        Raises
        ------
        ValueError
            Naming the field and the value when the configuration is invalid.
        """
        return _config.engine_config(self._data)

    def normalized(self) -> Configuration:
        """The configuration validated by the engine, every default explicit (:meth:`from_dict`)."""
        return type(self).from_dict(self._data)

    def replace(self, changes: dict | None = None, /, **blocks) -> Configuration:
        """A copy with some keys or blocks changed (not validated: :meth:`engine` does that).

        Parameters
        ----------
        changes : dict, optional
            Dotted path -> value: ``{"simulation.dt_s": 1e-4, "top_drive.controller.kp_nms_rad": 2e3}``;
            a missing block on the way is created, None removes the key.
        **blocks
            Whole blocks or top-level keys: ``law=thesis_law("tucker_wang")`` (a dict or a :class:`Block`),
            ``name="field-2"``; None removes it. Applied before ``changes``.

        Returns
        -------
        Configuration

        Raises
        ------
        AttributeError
            Naming the path for a key the configuration's schema does not have.
        """
        data = _copy(self._data)
        for name, value in blocks.items():
            _checked_path(name)
            if value is None:
                data.pop(name, None)
            else:
                data[name] = _copy(value)
        for path, value in (changes or {}).items():
            keys = _checked_path(path)
            node = data
            for key in keys[:-1]:
                node = node.setdefault(key, {})
            if value is None:
                node.pop(keys[-1], None)
            else:
                node[keys[-1]] = _copy(value)
        return type(self)._owning(data)

    def with_overrides(self, **overrides) -> Configuration:
        """A normalized copy with command-line style overrides (:func:`drillpy.model.config.with_overrides`:
        ``elements``, ``modes``, ``law``, ``beta1``, ``dt``, ``duration``, ``top_speed``, ``wob``...).

        Parameters
        ----------
        **overrides
            The keywords of :func:`drillpy.model.config.with_overrides`.

        Returns
        -------
        Configuration

        Raises
        ------
        ValueError
            Naming the field and the value for an invalid override.
        """
        return type(self)._owning(_config.with_overrides(self._data, **overrides))

    def __eq__(self, other) -> bool:
        if isinstance(other, Configuration):
            return self._data == other._data
        return NotImplemented

    def __reduce__(self):
        return (type(self), (self._data,))

    __hash__ = None
