"""NormalStreams hands out each env's generator's normals in order, whatever mix of
single pairs, peeked windows and resets: the same numbers, and the generator left in the
same state, as drawing one block of 64 pairs whenever the last one runs out (0.2.0)."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from bbgym.envs.common import NormalStreams

BATCH = 3


class Reference:
    """The 0.2.0 semantics, env by env."""

    def __init__(self, seeds: list[int]) -> None:
        self.rngs = [np.random.default_rng(s) for s in seeds]
        self.buf = [np.zeros((0, 2)) for _ in seeds]
        self.pos = [0 for _ in seeds]

    def take(self, i: int) -> np.ndarray:
        if self.pos[i] >= len(self.buf[i]):
            self.buf[i], self.pos[i] = self.rngs[i].standard_normal((64, 2)), 0
        self.pos[i] += 1
        return self.buf[i][self.pos[i] - 1]

    def discard(self, i: int) -> None:
        self.pos[i] = len(self.buf[i])


operation = st.one_of(
    st.tuples(st.just("pairs"), st.lists(st.booleans(), min_size=BATCH, max_size=BATCH)),
    st.tuples(
        st.just("peek"),
        st.lists(st.booleans(), min_size=BATCH, max_size=BATCH),
        st.integers(1, 150),
        st.lists(st.floats(0.0, 1.0), min_size=BATCH, max_size=BATCH),
    ),
    st.tuples(st.just("reset"), st.lists(st.booleans(), min_size=BATCH, max_size=BATCH)),
)


@settings(max_examples=150, deadline=None)
@given(st.lists(operation, min_size=1, max_size=40), st.integers(0, 2**16))
def test_streams_match_block_draws(ops: list, seed: int) -> None:
    seeds = [seed + i for i in range(BATCH)]
    streams, ref = NormalStreams(BATCH), Reference(seeds)
    streams.seed(seeds)
    for op in ops:
        mask = np.array(op[1])
        if op[0] == "pairs":
            got = streams.pairs(mask)
            for i in range(BATCH):
                want = ref.take(i) if mask[i] else np.zeros(2)
                np.testing.assert_array_equal(got[:, i], want)
        elif op[0] == "peek":
            count, fraction = op[2], op[3]
            window = streams.peek(mask, count)
            used = np.where(mask, (np.array(fraction) * count).astype(int), 0)
            streams.advance(used)
            for i in range(BATCH):
                for k in range(used[i]):
                    np.testing.assert_array_equal(window[k, :, i], ref.take(i))
        else:  # a reset: unused pairs go, then the reset draws from the generator itself
            streams.discard(mask)
            for i in np.flatnonzero(mask):
                ref.discard(i)
                np.testing.assert_array_equal(streams.rngs[i].random(3), ref.rngs[i].random(3))
    for i in range(BATCH):
        assert streams.rngs[i].random() == ref.rngs[i].random()


def test_single_env_one_matches_pairs() -> None:
    a, b = NormalStreams(1), NormalStreams(1)
    a.seed([5])
    b.seed([5])
    for step in range(200):
        draw = step % 3 != 0
        got = a.one(draw)
        want = b.pairs(np.array([draw]))[:, 0]
        assert got == tuple(want)
