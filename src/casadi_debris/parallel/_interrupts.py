"""Ctrl-C seen by a map even where Python drops the ``KeyboardInterrupt`` it raises.

Python runs a signal's handler in the main thread between two bytecodes, wherever
they are, and the ``KeyboardInterrupt`` that the default handler raises is lost
("Exception ignored in ...") when that place is a fork hook, a finaliser
(``__del__``, a weak reference's callback) or compiled code that catches it:
``logging``'s fork hook, run by every worker started, dropped a Ctrl-C typed while
a campaign started its workers, and the campaign ran to its end; CasADi turns a
Ctrl-C during an IPOPT solve into a failed solve. While a map runs, its handler
also notes the Ctrl-C and wakes the map's wait, which raises ``KeyboardInterrupt``
itself at its next step.
"""

from __future__ import annotations

import contextlib
import signal
import socket
import threading
from collections.abc import Iterator
from types import FrameType, TracebackType
from typing import Any


class Interrupts:
    """Within ``with Interrupts() as interrupts:``, Ctrl-C is noted and never lost.

    Outside the main thread, or when Ctrl-C is ignored or left to the system
    (``SIG_IGN``, ``SIG_DFL``), it changes nothing and notes nothing.

    Attributes
    ----------
    wakeup : socket.socket or None
        Readable once Ctrl-C came: wait on it together with the workers.
    """

    def __init__(self) -> None:
        self.seen = False
        self.wakeup: socket.socket | None = None
        self._sender: socket.socket | None = None
        self._previous: Any = None

    def __enter__(self) -> Interrupts:
        if threading.current_thread() is not threading.main_thread():
            return self
        previous = signal.getsignal(signal.SIGINT)
        if not callable(previous):
            return self
        self.wakeup, self._sender = socket.socketpair()
        self._sender.setblocking(False)
        self._previous = previous
        signal.signal(signal.SIGINT, self._handle)
        return self

    def _handle(self, number: int, frame: FrameType | None) -> None:
        self.seen = True
        if self._sender is not None:
            with contextlib.suppress(OSError):  # already woken
                self._sender.send(b"\0")
        self._previous(number, frame)  # KeyboardInterrupt, if Python does not drop it

    def check(self) -> None:
        """Raise ``KeyboardInterrupt`` if Ctrl-C came (and was dropped where it was raised)."""
        if self.seen:
            raise KeyboardInterrupt

    def __exit__(
        self,
        kind: type[BaseException] | None,
        error: BaseException | None,
        trace: TracebackType | None,
    ) -> None:
        if self._previous is not None and signal.getsignal(signal.SIGINT) == self._handle:
            signal.signal(signal.SIGINT, self._previous)
        for end in (self.wakeup, self._sender):
            if end is not None:
                end.close()
        self.wakeup = self._sender = None


@contextlib.contextmanager
def keep_ctrl_c() -> Iterator[None]:
    """Ctrl-C during the block ends it with ``KeyboardInterrupt``, even where compiled code
    inside turned it into an error or a failed result (CasADi's IPOPT: a
    ``RuntimeError``, or a solve that "did not converge").

    Wrap each solve that is not inside a map (whose own wait does the same):

    >>> with keep_ctrl_c():  # doctest: +SKIP
    ...     solution = opti.solve()
    """
    with Interrupts() as interrupts:
        try:
            yield
        except Exception as error:
            if interrupts.seen:
                raise KeyboardInterrupt from error
            raise
        interrupts.check()
