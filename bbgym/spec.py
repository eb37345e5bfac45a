"""What an env family declares, and the one registry of them.

An env family (``bbgym/envs/<family>/``) describes itself in one :class:`EnvSpec`: its env
ids and what each version changes, its Gymnasium classes, its task core and parameter
groups, its presets, its policies (scripted, planner, ...), its fuzz sampler, how its
episodes end for the failure breakdown, and its keyboard controls. Registration with
Gymnasium, the ``bbgym`` command, fuzzing, presets, RL Zoo files, bench and evaluation
loop over the registered specs, so no module outside a family's folder names one of its
env ids. ``docs/new-env.md`` is the checklist for adding a family.

A spec declares; it does not import its family's heavy parts: policies, samplers and the
like are callables that import what they need when called.
"""

from __future__ import annotations

import dataclasses
import difflib
import importlib
import inspect
from collections.abc import Callable, Iterable, Iterator, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from gymnasium.envs.registration import register, registry

Policy = Callable[[Any], Any]
"""``policy(obs) -> action``; it may also have ``reset()``, called at each episode's start."""
PolicyFactory = Callable[[Any], Policy]
"""``factory(env) -> policy`` for a single env made by ``gym.make`` (wrapped)."""


@dataclass(frozen=True)
class Version:
    """One registered env id of a family."""

    env_id: str
    """The Gymnasium id, ``"Name-vN"``."""
    changes: str
    """What this version changes against the family's first (one sentence, for the docs)."""
    kwargs: Mapping[str, Any] = field(default_factory=dict)
    """The keyword arguments it is registered with (on top of the task's defaults)."""
    preset: str | Path | None = None
    """Its training preset: a shipped file's name in ``bbgym/configs`` (``"beachball_sail"``)
    or a path. A preset of the family's base task gets ``kwargs`` on top."""
    base: bool = False
    """Whether it is a base task whose arguments the fuzzer draws freely (the others are
    fixed points of the same arguments) and which ``bbgym bench`` times by default."""
    actions: str | None = None
    """What its actions are, where they differ from the family's ``EnvSpec.actions``."""

    def actions_of(self, spec: EnvSpec) -> str:
        """What this version's actions are (its own words, else the family's).

        Args:
            spec: The family this version belongs to (its :attr:`EnvSpec.actions` is the
                fallback).

        Returns:
            A few words for the docs' table: :attr:`actions` if set, else ``spec.actions``.
        """
        return self.actions or spec.actions


@dataclass(frozen=True)
class FuzzSpec:
    """How :mod:`bbgym.fuzz` draws a family's arguments and options."""

    sample_kwargs: Callable[[Version, Any], dict[str, Any]]
    """``sample_kwargs(version, draw)``: constructor arguments over their accepted
    intervals (``draw`` is a :data:`bbgym.fuzz.Draw`)."""
    sample_options: Callable[[Any, Any], dict[str, Any] | None]
    """``sample_options(task, draw)``: ``reset`` options for a task made with some kwargs."""
    step_share: float = 1.0
    """Relative share of a fuzz run's env steps (a cheap step gets more)."""
    episode_steps: int = 8
    """Steps per drawn configuration."""
    fit: Callable[[dict[str, Any]], dict[str, Any]] | None = None
    """``fit(kwargs)``: the drawn arguments, with the version's pinned ones in place, made
    to meet the constraints between arguments that the family's validation refuses
    otherwise (a ball heavy enough for an RK4 step); ``None``: there are none."""


@dataclass(frozen=True)
class Showcase:
    """An episode that shows what a family is about, and the pace a person can follow it
    at: what ``bbgym baseline`` records of the learnt policy (``episode.gif``)."""

    seed: int = 0
    """The episode's reset seed."""
    frame_skip: int = 2
    """Every ``frame_skip``-th frame is kept (the key frames always)."""
    fps: float = 20.0
    """Frames per second of the animation."""


@dataclass(frozen=True)
class EnvSpec:
    """An env family: everything the package's shared machinery needs to know of it."""

    family: str
    """The folder's name under ``bbgym/envs/`` (``"sail"``); the classes live in
    ``bbgym.envs.<family>``."""
    env_class: str
    """The single env's class name in ``bbgym.envs.<family>``."""
    vector_env_class: str
    """The native vector env's class name in ``bbgym.envs.<family>``."""
    max_episode_steps: int
    """The step limit every id is registered with (Gymnasium's ``TimeLimit`` truncates the
    episode after this many steps)."""
    versions: tuple[Version, ...]
    """The family's registered ids, oldest first."""
    summary: str
    """What the task is, in one line (``bbgym --help``, the docs)."""
    actions: str
    """What the actions are, in a few words (the docs' table)."""
    param_groups: Mapping[str, type] = field(default_factory=dict)
    """Constructor arguments that take a parameter dataclass (``"dinghy": DinghyParams``):
    the fuzzer draws and checks every field of each."""
    jax_params: tuple[str, ...] = ()
    """The constructor arguments that may vary inside a JAX program, by path
    (``"dinghy.mass_kg"``, ``"wind_speed_range"``): the leaves of
    :class:`bbgym.jax_env.EnvParams`, which ``jax.vmap`` batches (domain randomization).
    Each is one the task builds from without branching on its value; a test checks that
    a traced value steps as a task built with it."""
    shorthands: Mapping[str, str] = field(default_factory=dict)
    """Constructor arguments that set a parameter group's field (``"sail_model":
    "dinghy.sail_model"``): a user's value for either spelling replaces a version's value
    of both (:func:`merge_kwargs`)."""
    integer_arguments: tuple[str, ...] = ()
    """Constructor arguments that take an int (the rest of the numbers are floats)."""
    policies: Mapping[str, PolicyFactory] = field(default_factory=dict)
    """Non-learning policies by name: ``scripted`` (the family's scripted agent), and where
    it has them ``planner`` (privileged: it may read the true state) and others."""
    timed_by_oracle: bool = False
    """Whether ``bbgym evaluate`` compares each policy's time with the scripted policy's
    (``time / oracle``; the env's info has ``elapsed_time``)."""
    outcome: Callable[[Any, dict[str, Any], bool, bool], tuple[str, bool]] | None = None
    """``outcome(env, info, terminated, truncated) -> (text, success)`` of an episode that
    ended: the text captions a recording, and a failure's text is its row in the failure
    breakdown (``"capsized"``, ``"missed long"``); by default success, timed out or failed."""
    fuzz: FuzzSpec | None = None
    """How :mod:`bbgym.fuzz` draws the family's arguments and options; ``None``: the
    family is not fuzzed."""
    keyboard: Callable[[Any, int | None], Any] | None = None
    """``keyboard(env, seed)``: the env wrapped for ``bbgym play``."""
    argument_table: tuple[tuple[str, str], ...] = ()
    """The accepted values of the constructor's arguments and the reset options, as
    ``(arguments, accepted)`` rows of the documentation's table (the parameter groups'
    fields have their own rows, from their dataclasses' intervals)."""
    step_unit: str = "steps"
    """What an env step is, for throughput figures (``"throws"`` for a ball env)."""
    demo: Callable[[int | None, int], tuple[str, str, dict[str, Any], list[Any]]] | None = None
    """``demo(seed, frame_skip) -> (caption, statistics table, statistics, frames)``: one
    scripted episode for ``bbgym demo`` (``seed`` None: the family's showcase seed)."""
    showcase: Showcase = field(default_factory=Showcase)
    """The episode ``bbgym baseline`` records, and at what pace."""
    classes_module: str | None = None
    """The module that holds the two classes, if not ``bbgym.envs.<family>`` (a family
    declared outside the package, such as the test suite's)."""

    @property
    def module(self) -> str:
        """The module that holds the env classes: :attr:`classes_module`, else
        ``bbgym.envs.<family>``."""
        return self.classes_module or f"bbgym.envs.{self.family}"

    @property
    def ids(self) -> tuple[str, ...]:
        """The family's env ids, in the order of :attr:`versions`."""
        return tuple(v.env_id for v in self.versions)

    def argument_rows(self) -> tuple[tuple[str, str], ...]:
        """The documentation's rows of the constructor's arguments and reset options:
        :attr:`argument_table`, or where it is empty and the task's arguments are one
        dataclass (``params_class``), a row per field, from the interval it declares (the
        one the validation checks): one source for the check and the table.

        Returns:
            ``(arguments, accepted)`` rows.
        """
        if self.argument_table:
            return tuple(self.argument_table)
        env_class = getattr(importlib.import_module(self.module), self.env_class)
        params_class = getattr(getattr(env_class, "task_class", None), "params_class", None)
        if params_class is None:
            return ()
        return tuple(
            (f"`{f.name}`", str(f.metadata["interval"]))
            for f in dataclasses.fields(params_class)
            if "interval" in f.metadata
        )

    def version(self, env_id: str) -> Version:
        """One of the family's versions, by its id.

        Args:
            env_id: A Gymnasium id of this family, ``"Name-vN"``.

        Returns:
            The version registered as ``env_id`` (a :class:`Version`).

        Raises:
            KeyError: If the family has no version ``env_id``.
        """
        for v in self.versions:
            if v.env_id == env_id:
                return v
        raise KeyError(env_id)

    def policy(self, name: str, env: Any) -> Policy:
        """The named non-learning policy for ``env``; ``ValueError`` if the family has none.

        Args:
            name: A key of :attr:`policies`: ``"scripted"``, and where the family has them
                ``"planner"`` and others.
            env: A single env of this family made by ``gym.make`` (wrapped or not).

        Returns:
            ``policy(obs) -> action`` for ``env`` (:data:`Policy`).

        Raises:
            ValueError: If the family has no policy ``name``; the message lists those it has.
        """
        if name not in self.policies:
            raise ValueError(
                f"{env_id_of(env)!r} has no {name!r} policy; it has: "
                f"{', '.join(sorted(self.policies)) or 'none'}"
            )
        return self.policies[name](env)

    def episode_outcome(
        self, env: Any, info: dict[str, Any], terminated: bool, truncated: bool
    ) -> tuple[str, bool | None]:
        """``(text, success)`` of an episode from its last step; ``success`` is None for an
        episode cut short (neither terminated nor truncated).

        Args:
            env: The env the episode ran in.
            info: The ``info`` of the episode's last step.
            terminated: The last step's ``terminated`` flag.
            truncated: The last step's ``truncated`` flag (the time limit).

        Returns:
            ``(text, success)``: the family's :attr:`outcome` where it has one, else
            ``("success", True)``, ``("failed", False)`` or ``("timed out", False)``; for
            an episode that neither terminated nor truncated, ``("cut short
            (--max-steps)", None)``.
        """
        if not (terminated or truncated):
            return "cut short (--max-steps)", None
        if self.outcome is not None:
            return self.outcome(env, info, terminated, truncated)
        if bool(info.get("is_success", False)):
            return "success", True
        return ("failed", False) if terminated else ("timed out", False)


AgentsEpisode = Iterator[tuple[Any, str]]
"""One recorded episode of every agent: ``(frame, caption)`` pairs, a frame per step and
the first; the generator returns the episode's statistics (``steps``, ``outcome`` in words,
``capped``: cut by ``max_steps``, and the family's own)."""


@dataclass(frozen=True)
class MultiAgentFuzz:
    """How ``bbgym fuzz`` fuzzes a family of many agents (:attr:`MultiAgentSpec.fuzz`): its
    forms stepped in turn, each check's length, and the family's samplers and checks."""

    forms: tuple[str, ...]
    """The env's forms a check steps in turn (``("parallel", "aec")``)."""
    episode_steps: int
    """Steps of one check (a failure counts them all: a failing episode still ends)."""
    sample_kwargs: Callable[[Any], dict[str, Any]]
    """``sample_kwargs(draw)``: constructor arguments over their accepted intervals."""
    sample_options: Callable[[Any], dict[str, Any] | None]
    """``sample_options(draw)``: reset options, or ``None``."""
    check_episode: Callable[..., int]
    """``check_episode(kwargs, steps, seed, form, options)``: step random and bad actions,
    check every output; returns the agent steps taken."""
    check_rejections: Callable[[], int]
    """``check_rejections()``: every invalid number of every numeric argument raises an
    error naming it; returns how many were checked."""


@dataclass(frozen=True)
class MultiAgentSpec:
    """A family of many agents in one env (PettingZoo's), declared as :class:`EnvSpec`
    declares a Gymnasium family: what registration, ``bbgym record``, ``bbgym bench`` and
    the stable-baselines3 adapter need to know of it, so none of them names the family.

    Its ids are PettingZoo's (parallel and AEC) and a Gymnasium id of one agent against
    scripted others; none is in :func:`env_ids` (those are the single-agent families').
    Its classes live in ``bbgym.envs.<family>``, loaded only when made: the family's
    extra (PettingZoo) is imported then.
    """

    family: str
    """The folder's name under ``bbgym/envs/`` (``"race"``)."""
    env_id: str
    """The id in PettingZoo's registries (``pettingzoo.make("parallel", env_id)``)."""
    summary: str
    """What the task is, in one line (``bbgym --help``, the docs)."""
    extra: str
    """The extra that installs what the env needs (PettingZoo), named in its errors."""
    one_agent_env_id: str
    """A Gymnasium id of one agent against scripted others, for single-agent learners."""
    one_agent_env_class: str
    """That env's class name in ``bbgym.envs.<family>``."""
    vector_env_classes: tuple[str, ...]
    """The family's native Gymnasium vector envs (class names), which restart what a step
    ended on the next step and offer ``reset_envs`` (the stable-baselines3 adapter takes
    them); the first, ``first(num_episodes, num_agents=..., **backend)``, runs every agent
    of ``num_episodes`` episodes (what ``bbgym bench`` times)."""
    agents: int
    """Agents an episode has by default (the bench rows' episodes)."""
    agents_argument: str
    """The keyword of the envs' constructors that sets the agents an episode has
    (``"num_boats"``)."""
    parallel_env: str = "parallel_env"
    """The parallel env's factory in ``bbgym.envs.<family>``."""
    aec_env: str = "env"
    """The AEC env's factory in ``bbgym.envs.<family>``."""
    agent_name: str = "agent"
    """What an agent is called in the bench rows (``"boat"``)."""
    episode_name: str = "episode"
    """What an episode is called in the bench rows (``"race"``)."""
    policies: tuple[str, ...] = ()
    """What ``bbgym record`` sails every agent by (``"scripted"``, ``"random"``, ...)."""
    argument_table: tuple[tuple[str, str], ...] = ()
    """The accepted values of the constructor's arguments and the reset options, as
    ``(arguments, accepted)`` rows of the documentation's table."""
    param_groups: Mapping[str, type] = field(default_factory=dict)
    """Constructor arguments that take a parameter dataclass (the docs' tables list their
    fields)."""
    fuzz: str | None = None
    """Where ``bbgym fuzz`` finds the family's :class:`MultiAgentFuzz`, ``"module:name"``
    in its package (``"fuzz:FUZZ"``); ``None``: not fuzzed."""
    record: str | None = None
    """Where ``bbgym record`` finds the episode recorder, ``"module:function"`` in the
    family's package (``"recording:recorded_race"``): ``record(policy_name, seed=,
    max_steps=, model=, load_policy=)`` gives one episode of every agent as frames with
    captions (:data:`AgentsEpisode`); ``load_policy(env, model)`` is the command's loader
    of a saved model. A path, not the function: the spec imports none of its family."""

    @property
    def module(self) -> str:
        """The module that holds the env classes and factories: ``bbgym.envs.<family>``."""
        return f"bbgym.envs.{self.family}"

    def argument_rows(self) -> tuple[tuple[str, str], ...]:
        """The documentation's rows of the constructor's arguments and reset options.

        Returns:
            :attr:`argument_table`.
        """
        return tuple(self.argument_table)

    @property
    def step_unit(self) -> str:
        """What one agent's step is called in throughput figures (``"boat-steps"``)."""
        return f"{self.agent_name}-steps"

    @property
    def ids(self) -> tuple[str, ...]:
        """The family's ids: PettingZoo's, then the one-agent Gymnasium id."""
        return (self.env_id, self.one_agent_env_id)

    def load(self, name: str) -> Any:
        """One of the family's classes or factories, importing its module (and extra).

        Args:
            name: A name in ``bbgym.envs.<family>`` (:attr:`vector_env_classes`' first,
                ...), or ``"module:name"`` in one of its modules (:attr:`record`).

        Returns:
            The class or function.
        """
        module, _, attribute = name.rpartition(":")
        where = f"{self.module}.{module}" if module else self.module
        return getattr(importlib.import_module(where), attribute)

    def register_pettingzoo(self) -> None:
        """Register the family's parallel and AEC ids in PettingZoo's registries (by module
        path: PettingZoo imports the family at ``make``), once; where PettingZoo is not
        installed, nothing (``gym.make`` of the one-agent id names the extra)."""
        try:
            import pettingzoo
        except ImportError:
            return
        for kind, factory, known in (
            ("parallel", self.parallel_env, pettingzoo.parallel_registry),
            ("aec", self.aec_env, pettingzoo.aec_registry),
        ):
            if self.env_id not in known:
                pettingzoo.register(kind, self.env_id, entry_point=f"{self.module}:{factory}")


_SPECS: dict[str, EnvSpec] = {}
_BY_ID: dict[str, EnvSpec] = {}
_MULTI_AGENT: dict[str, MultiAgentSpec] = {}


def merge_kwargs(
    spec: EnvSpec, registered: Mapping[str, Any], given: Mapping[str, Any]
) -> dict[str, Any]:
    """A version's ``registered`` kwargs with a user's ``given`` ones on top, as ``gym.make``
    and ``gym.make_vec`` pass them to the env.

    A parameter group (:attr:`EnvSpec.param_groups`) the version registers as a mapping
    keeps it: a mapping given for it changes only the fields it names (``dinghy={"mass_kg":
    150}`` is Sail-v2's sloop, 150 kg), ``None`` keeps it, a dataclass replaces it
    whole. Any other argument given replaces the registered one. A shorthand
    (:attr:`EnvSpec.shorthands`) given one way drops the version's value given the other
    way, so that the user's value is the one used.

    Args:
        spec: The version's family (its :attr:`EnvSpec.param_groups` and
            :attr:`EnvSpec.shorthands`).
        registered: The kwargs the version is registered with (:attr:`Version.kwargs`).
        given: The kwargs the user passed to ``gym.make`` / ``gym.make_vec``.

    Returns:
        A new dict: the kwargs the env's constructor gets.
    """
    merged = {**registered, **given}
    for group in spec.param_groups:
        base = registered.get(group)
        if group not in given or not isinstance(base, Mapping):
            continue
        value = given[group]
        if value is None:
            merged[group] = base
        elif isinstance(value, Mapping):
            merged[group] = {**base, **value}
    for name, path in spec.shorthands.items():
        group, key = path.split(".", 1)
        value = given.get(group)
        sets_field = value is not None and (not isinstance(value, Mapping) or key in value)
        if name in given and not sets_field and isinstance(merged.get(group), Mapping):
            merged[group] = {k: v for k, v in merged[group].items() if k != key}
        elif sets_field and name not in given:
            merged.pop(name, None)
    return merged


NEAR_MATCH = 0.7
"""How alike (:class:`difflib.SequenceMatcher` ratio) a name a user typed must be to a known
one for an error to ask "did you mean"."""


def nearest(name: str, known: Iterable[str]) -> str | None:
    """The known name closest to ``name``, if one is near enough to be what the user meant.

    Args:
        name: The name as the user typed it.
        known: The names that exist.

    Returns:
        The nearest of ``known`` (at least :data:`NEAR_MATCH` alike), or ``None``.
    """
    close = difflib.get_close_matches(name, list(known), n=1, cutoff=NEAR_MATCH)
    return close[0] if close else None


class UnknownArgumentError(TypeError):
    """An env id made with a keyword argument that none of its constructors take.

    It is raised while ``gym.make`` / ``gym.make_vec`` merge the user's kwargs into the
    version's (:meth:`VersionKwargs.update`), before the env creator runs: there the error can
    name the id and the argument as the user passed it, and the registered (preset) kwargs
    the user never passed stay out of it. Gymnasium re-raises a ``TypeError`` from the env
    creator as ``type(e)(f"{e} was raised from the environment creator for {id} with kwargs
    ({every kwarg})")``; should this error ever come from there, the constructor keeps only
    the part before that suffix, so the message stays the one written here.

    Args:
        message: The error's text; Gymnasium's suffix, if any, is cut off.
        *args: Further exception arguments, kept as given.
    """

    _GYMNASIUM_SUFFIX = " was raised from the environment creator"

    def __init__(self, message: str = "", *args: Any) -> None:
        if isinstance(message, str):
            message = message.split(self._GYMNASIUM_SUFFIX, 1)[0]
        super().__init__(message, *args)


def _parameters(creator: Any) -> tuple[list[str], bool]:
    """``(names, open)``: the keyword arguments ``creator`` takes by name, and whether it
    takes ``**kwargs`` as well."""
    params_class = getattr(creator, "params_class", None)
    if params_class is not None:  # a task whose arguments are one dataclass's fields
        return [f.name for f in dataclasses.fields(params_class)], False
    names, open_ = [], False
    for parameter in inspect.signature(creator).parameters.values():
        if parameter.kind is parameter.VAR_KEYWORD:
            open_ = True
        elif parameter.kind in (parameter.POSITIONAL_OR_KEYWORD, parameter.KEYWORD_ONLY):
            names.append(parameter.name)
    return names, open_


def accepted_arguments(spec: EnvSpec) -> tuple[list[str], list[str]] | None:
    """The keyword arguments a family's envs take, from their constructors' signatures.

    Args:
        spec: The family.

    Returns:
        ``(arguments, vector_only)``: what ``gym.make`` takes (the task's arguments and
        ``render_mode``), and what only the native vector env takes on top (``backend``,
        ...); ``None`` where a constructor takes any keyword (nothing to check against).
    """
    module = importlib.import_module(spec.module)
    lists = []
    for class_name in (spec.env_class, spec.vector_env_class):
        cls = getattr(module, class_name)
        names, open_ = _parameters(cls)
        if open_:
            task_class = getattr(cls, "task_class", None)
            if task_class is None:
                return None
            task_names, task_open = _parameters(task_class)
            if task_open:
                return None
            names = [n for n in names if n not in task_names] + task_names
        lists.append([n for n in names if n != "num_envs"])
    single, vector = lists
    return single, [n for n in vector if n not in single]


def check_arguments(spec: EnvSpec, env_id: str, given: Iterable[Any]) -> None:
    """Raise :class:`UnknownArgumentError` for a keyword argument no env of ``env_id`` takes.

    Its message names the id, the argument as passed and the nearest accepted one ("did you
    mean"); only where none is near, it lists the accepted ones.

    Args:
        spec: ``env_id``'s family.
        env_id: The id the user made.
        given: The names of the user's keyword arguments.

    Raises:
        UnknownArgumentError: For the first unknown name.
    """
    accepted = accepted_arguments(spec)
    if accepted is None:
        return
    single, vector_only = accepted
    for name in given:
        if name in single or name in vector_only:
            continue
        text = name if isinstance(name, str) else str(name)
        message = f"{env_id} got an unknown argument {name!r}"
        near = nearest(text, single + vector_only)
        if near is not None:
            raise UnknownArgumentError(f"{message}; did you mean {near!r}?")
        raise UnknownArgumentError(
            f"{message}; its arguments: {', '.join(single)}"
            f" (and for its native vector env: {', '.join(vector_only)})"
        )


class VersionKwargs(dict):
    """The kwargs a version is registered with (``gym.spec(env_id).kwargs``).

    ``gym.make`` and ``gym.make_vec`` copy them and ``update`` the copy with the user's
    kwargs: a plain dict's update would replace a parameter group whole, so that
    ``dinghy={"mass_kg": 150}`` dropped Sail-v2's sloop for the default cat rig.
    This update is :func:`merge_kwargs`. It first checks the user's kwargs
    (:func:`check_arguments`): an unknown one raises :class:`UnknownArgumentError` naming
    the id, rather than the task class's ``TypeError`` with the version's preset kwargs
    appended by ``gym.make``. (A copy that ``dataclasses.asdict`` makes has no ``family``
    and updates as a dict: it is only ever turned into JSON.)"""

    family: str | None = None
    """The family whose spec merges updates (``None``: a plain dict's update)."""
    env_id: str | None = None
    """The id these kwargs are registered for, named in an unknown argument's error
    (``None``: the user's kwargs are not checked)."""

    @classmethod
    def of(cls, family: str, kwargs: Mapping[str, Any], env_id: str | None = None) -> VersionKwargs:
        """A version's registered kwargs that merge a user's kwargs in as its family does.

        Args:
            family: The family's name (:attr:`EnvSpec.family`).
            kwargs: The version's kwargs (:attr:`Version.kwargs`).
            env_id: The version's id; ``None``: a user's kwargs are merged unchecked.

        Returns:
            A copy of ``kwargs`` as a :class:`VersionKwargs`.
        """
        registered = cls(kwargs)
        registered.family = family
        registered.env_id = env_id
        return registered

    def update(self, other: Any = (), /, **kwargs: Any) -> None:
        """Merge a user's kwargs in (:func:`merge_kwargs`), after checking their names.

        Args:
            other: A mapping or iterable of ``(name, value)`` pairs, as ``dict.update``
                takes.
            **kwargs: More ``name=value`` kwargs, on top of ``other``.

        Raises:
            UnknownArgumentError: If a name is an argument no env of :attr:`env_id` takes.
        """
        given = dict(other, **kwargs)
        spec = _SPECS.get(self.family) if self.family is not None else None
        if spec is None:
            super().update(given)
            return
        if self.env_id is not None:
            check_arguments(spec, self.env_id, given)
        merged = merge_kwargs(spec, self, given)
        self.clear()
        super().update(merged)


def register_spec(spec: EnvSpec | MultiAgentSpec) -> EnvSpec | MultiAgentSpec:
    """Add ``spec`` to the registry and register each of its ids with Gymnasium (single
    and native vector entry points; a :class:`MultiAgentSpec`'s one-agent id, and its
    PettingZoo ids where PettingZoo is installed). Registering the same family again
    replaces it.

    Args:
        spec: The family to register.

    Returns:
        ``spec`` itself.

    Raises:
        ValueError: If one of its ids is registered by another family.
    """
    if isinstance(spec, MultiAgentSpec):
        _MULTI_AGENT[spec.family] = spec
        registry.pop(spec.one_agent_env_id, None)
        register(id=spec.one_agent_env_id, entry_point=f"{spec.module}:{spec.one_agent_env_class}")
        spec.register_pettingzoo()
        return spec
    for version in spec.versions:
        owner = _BY_ID.get(version.env_id)
        if owner is not None and owner.family != spec.family:
            raise ValueError(f"{version.env_id} is already registered by {owner.family!r}")
    old = _SPECS.pop(spec.family, None)
    if old is not None:
        for env_id in old.ids:
            _BY_ID.pop(env_id, None)
    _SPECS[spec.family] = spec
    for version in spec.versions:
        _BY_ID[version.env_id] = spec
        registry.pop(version.env_id, None)
        register(
            id=version.env_id,
            entry_point=f"{spec.module}:{spec.env_class}",
            vector_entry_point=f"{spec.module}:{spec.vector_env_class}",
            max_episode_steps=spec.max_episode_steps,
            kwargs=VersionKwargs.of(spec.family, version.kwargs, version.env_id),
        )
    return spec


def unregister_spec(family: str) -> None:
    """Remove a family and its ids (from Gymnasium's registry too).

    Args:
        family: The family's name (:attr:`EnvSpec.family`), e.g. ``"sail"``.

    Raises:
        KeyError: If no family of that name is registered.
    """
    spec = _SPECS.pop(family)
    for env_id in spec.ids:
        _BY_ID.pop(env_id, None)
        registry.pop(env_id, None)


def multi_agent_specs() -> Iterator[MultiAgentSpec]:
    """The registered families of many agents (:class:`MultiAgentSpec`), in registration
    order.

    Returns:
        An iterator over a snapshot of them.
    """
    return iter(list(_MULTI_AGENT.values()))


def multi_agent_spec_of(env_id: str) -> MultiAgentSpec | None:
    """The family of many agents that registered ``env_id`` (its PettingZoo id or its
    one-agent id), or ``None``.

    Args:
        env_id: An id, such as a PettingZoo id ``"bbgym/Name-vN"``.

    Returns:
        The family's spec, or ``None`` where no such family has that id.
    """
    return next((s for s in _MULTI_AGENT.values() if env_id in s.ids), None)


def is_native_vector_env(env: Any) -> bool:
    """Whether ``env`` is one of bbgym's native vector envs (a registered family's: it
    restarts what a step ended on the next step and offers ``reset_envs``).

    Args:
        env: Any object.

    Returns:
        True for an instance of a family's vector env class or a subclass of one.
    """
    classes = [(s.module, (s.vector_env_class,)) for s in _SPECS.values()]
    classes += [(s.module, s.vector_env_classes) for s in _MULTI_AGENT.values()]
    return any(
        klass.__name__ in names and klass.__module__.startswith(module)
        for klass in type(env).__mro__
        for module, names in classes
    )


def specs() -> Iterator[EnvSpec]:
    """The registered families, in registration order.

    Returns:
        An iterator over a snapshot of the registry: registering or removing a family
        while iterating is safe.
    """
    return iter(list(_SPECS.values()))


def spec_of_class(cls: type) -> EnvSpec:
    """The family whose single or vector env class ``cls`` is (or derives from), by the
    class's name and module; ``LookupError`` if none registered it.

    Args:
        cls: An env class (``BeachballSailVectorEnv``) or a subclass of one.

    Returns:
        The family's spec.

    Raises:
        LookupError: If no registered family declares ``cls`` or one of its bases.
    """
    for klass in cls.__mro__:
        for spec in specs():
            names = (spec.env_class, spec.vector_env_class)
            if klass.__name__ in names and klass.__module__.startswith(spec.module):
                return spec
    raise LookupError(f"{cls.__name__} is the env class of no registered bbgym family")


def spec_of(env_id: str) -> EnvSpec:
    """The family of a registered bbgym id; ``ValueError`` naming the known ids if none.

    Args:
        env_id: A Gymnasium id, ``"Name-vN"``.

    Returns:
        The spec of the family that registered ``env_id``.

    Raises:
        ValueError: If no family registered ``env_id``; the message lists the known ids.
    """
    try:
        return _BY_ID[env_id]
    except KeyError:
        raise ValueError(f"unknown env id {env_id!r}; known: {', '.join(env_ids())}") from None


def env_ids() -> list[str]:
    """Every registered bbgym id.

    Returns:
        The ids, family by family in registration order, each family's oldest first.
    """
    return list(_BY_ID)


def base_ids() -> list[str]:
    """The ids of the base tasks (:attr:`Version.base`): what fuzzing and bench cover.

    Returns:
        The ids with ``base=True``, in registration order.
    """
    return [v.env_id for s in _SPECS.values() for v in s.versions if v.base]


def newest_ids() -> list[str]:
    """The newest version of every task (the highest ``-vN`` of each name), in registration
    order: what ``bbgym bench`` times by default, so that it makes no env
    Gymnasium calls out of date.

    Returns:
        One id per task name, in the order the names were first registered.
    """
    newest: dict[str, tuple[int, str]] = {}
    for spec in _SPECS.values():
        for version in spec.versions:
            name, _, number = version.env_id.rpartition("-v")
            if name not in newest or int(number) > newest[name][0]:
                newest[name] = (int(number), version.env_id)
    return [env_id for _, env_id in newest.values()]


def env_id_of(env: Any) -> str:
    """The id an env was made with (``""`` for one made without ``gym.make``).

    Args:
        env: A single or vector env, wrapped or not.

    Returns:
        ``env.spec.id``, or ``""`` where the env has no spec.
    """
    spec = getattr(env, "spec", None)
    return spec.id if spec is not None else ""
