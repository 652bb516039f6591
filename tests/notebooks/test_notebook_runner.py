"""notebooks/run.py: every wait on a kernel socket is a chain of short polls, so a lost
wake-up (a message that arrived without waking the poll) costs at most one slice — and is
counted; a real timeout still raises."""

import asyncio
import importlib.util
import time
from pathlib import Path
from queue import Empty

import pytest

spec = importlib.util.spec_from_file_location(
    "nb_run", Path(__file__).resolve().parents[2] / "notebooks" / "run.py")
run = importlib.util.module_from_spec(spec)
spec.loader.exec_module(run)


class FakeDate:
    def __init__(self, ts):
        self.ts = ts

    def timestamp(self):
        return self.ts


def channel(sent_at, seen_after):
    """A get_msg whose message is sent at ``sent_at`` but only seen ``seen_after`` s later
    (a lost wake-up that a later poll's direct check finds)."""
    async def get_msg(timeout=None):
        now = time.time()
        if now >= sent_at + seen_after:
            return {"header": {"date": FakeDate(sent_at)}, "content": {}}
        wait = min(timeout if timeout is not None else 1e9, sent_at + seen_after - now)
        await asyncio.sleep(wait)
        if time.time() >= sent_at + seen_after:
            return {"header": {"date": FakeDate(sent_at)}, "content": {}}
        raise Empty
    return get_msg


def test_a_late_message_is_returned_and_counted(monkeypatch):
    monkeypatch.setattr(run, "SLICE_S", 0.05)
    counter = [0]
    get = run.sliced(channel(time.time() + 0.02, 0.3), counter)
    msg = asyncio.run(get(timeout=5))
    assert msg["content"] == {} and counter == [1]


def test_a_prompt_message_is_not_counted(monkeypatch):
    monkeypatch.setattr(run, "SLICE_S", 0.05)
    counter = [0]
    get = run.sliced(channel(time.time() + 0.02, 0.0), counter)
    asyncio.run(get(timeout=5))
    assert counter == [0]


def test_the_timeout_still_holds(monkeypatch):
    monkeypatch.setattr(run, "SLICE_S", 0.05)
    get = run.sliced(channel(time.time() + 100, 0.0), [0])
    t0 = time.monotonic()
    with pytest.raises(Empty):
        asyncio.run(get(timeout=0.2))
    assert 0.15 < time.monotonic() - t0 < 2


def test_an_unknown_notebook_prefix_is_a_usage_error(capsys):
    assert run.main(["99"]) == 2
    assert "no notebook starts with 99" in capsys.readouterr().err
