"""An existing Dask scheduler given by ``--scheduler``: its address checked, then probed, then used.

A Dask client trusts what the peer sends: the first 8 bytes it reads are the size of the message
to allocate. A port that answers with something else (an HTTP or SSH server, random bytes) can
make it ask for exabytes (a MemoryError) or wait for ever. So before the client connects, vlab
opens a plain socket (CONNECT_TIMEOUT_S), reads the handshake a Dask scheduler sends unasked as
soon as a connection opens — an 8-byte little-endian length n, then n bytes: a frame count, the
frame lengths and a msgpack map that names "compression" — and accepts the address only if n is
at most MAX_HANDSHAKE_BYTES and the frames add up. Nothing is allocated from an unchecked length.
"""

from __future__ import annotations

import re
import socket
import struct

CONNECT_TIMEOUT_S = 5.0
MAX_HANDSHAKE_BYTES = 64 * 1024
MAX_FRAMES = 64
_ADDRESS = re.compile(r"^(?:tcp://)?(\[[0-9A-Fa-f:.]+\]|[A-Za-z0-9](?:[A-Za-z0-9.-]{0,252}))?:(\d{1,5})$")
FORM = "tcp://HOST:PORT (e.g. tcp://127.0.0.1:8786)"


class SchedulerError(ValueError):
    """--scheduler is malformed, unreachable or not a Dask scheduler (exit 2)."""


def parse_address(address: str) -> tuple[str, int]:
    """``tcp://HOST:PORT`` (or ``HOST:PORT``) -> (host, port); SchedulerError otherwise."""
    m = _ADDRESS.match(address.strip()) if isinstance(address, str) else None
    if not m or not m.group(1) or not 1 <= int(m.group(2)) <= 65535:
        raise SchedulerError(f"--scheduler {address!r} is not an address of the form {FORM}")
    return m.group(1).strip("[]"), int(m.group(2))


def _read_exactly(sock: socket.socket, n: int) -> bytes:
    data = bytearray()
    while len(data) < n:
        chunk = sock.recv(n - len(data))
        if not chunk:
            break
        data += chunk
    return bytes(data)


def _is_handshake(body: bytes) -> bool:
    if len(body) < 8:
        return False
    (count,) = struct.unpack("<Q", body[:8])
    if not 1 <= count <= MAX_FRAMES or len(body) < 8 * (1 + count):
        return False
    lengths = struct.unpack(f"<{count}Q", body[8:8 * (1 + count)])
    return 8 * (1 + count) + sum(lengths) == len(body) and b"compression" in body


def probe(address: str, timeout: float = CONNECT_TIMEOUT_S) -> None:
    """Raise SchedulerError unless a Dask scheduler answers at ``address`` within ``timeout``."""
    host, port = parse_address(address)
    try:
        with socket.create_connection((host, port), timeout=timeout) as sock:
            sock.settimeout(timeout)
            head = _read_exactly(sock, 8)
            size = struct.unpack("<Q", head)[0] if len(head) == 8 else None
            ok = size is not None and 0 < size <= MAX_HANDSHAKE_BYTES and _is_handshake(_read_exactly(sock, size))
    except socket.timeout:
        raise SchedulerError(f"--scheduler {address!r}: no Dask scheduler answered within {timeout:g} s") from None
    except OSError as exc:
        raise SchedulerError(f"--scheduler {address!r}: cannot connect ({exc.strerror or exc})") from None
    if not ok:
        raise SchedulerError(f"--scheduler {address!r}: the program listening there is not a Dask scheduler "
                             f"(its first reply is not a Dask handshake)")


def connect(address: str, timeout: float = CONNECT_TIMEOUT_S):
    """A distributed Client on the checked scheduler at ``address``."""
    from distributed import Client

    probe(address, timeout)
    try:
        return Client(address, timeout=f"{4 * timeout:g}s")
    except (OSError, TimeoutError, ValueError) as exc:
        raise SchedulerError(f"--scheduler {address!r}: the Dask client could not connect ({exc})") from None
