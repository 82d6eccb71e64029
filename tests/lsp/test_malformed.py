"""`qcsg lsp` as a process, fed raw bytes: it answers malformed JSON-RPC, keeps serving, and
exits with the status LSP asks for (0 after `shutdown`, 1 without).

No LSP client library here: the point is bytes no client library would send.
"""

import asyncio
import json

from conftest import QCSG

TIMEOUT = 20.0

INITIALIZE = {"jsonrpc": "2.0", "id": 1, "method": "initialize", "params": {"capabilities": {}}}


def frame(body: bytes) -> bytes:
    return b"Content-Length: %d\r\n\r\n" % len(body) + body


def message(value) -> bytes:
    return frame(json.dumps(value).encode())


class Server:
    """`qcsg lsp` in a subprocess, with its standard input kept open as an editor does."""

    def __init__(self, process):
        self.process = process
        self.received = []

    @classmethod
    async def start(cls):
        process = await asyncio.create_subprocess_exec(
            QCSG, "lsp", stdin=asyncio.subprocess.PIPE, stdout=asyncio.subprocess.PIPE
        )
        return cls(process)

    async def send(self, data: bytes):
        self.process.stdin.write(data)
        await self.process.stdin.drain()

    async def read_message(self):
        length = None
        while True:
            line = await self.process.stdout.readline()
            assert line, f"the server's output ended; received {self.received}"
            line = line.strip()
            if not line:
                break
            name, _, value = line.partition(b":")
            if name.lower() == b"content-length":
                length = int(value)
        return json.loads(await self.process.stdout.readexactly(length))

    async def response(self, id):
        async def wait():
            while True:
                received = await self.read_message()
                self.received.append(received)
                if "method" not in received and received.get("id") == id:
                    return received

        return await asyncio.wait_for(wait(), TIMEOUT)

    async def exit_status(self):
        await self.send(message({"jsonrpc": "2.0", "method": "exit"}))
        return await asyncio.wait_for(self.process.wait(), TIMEOUT)


async def test_garbage_then_initialize_is_answered():
    server = await Server.start()
    await server.send(
        b"\x00\xff\xfe garbage\r\n\r\n"  # not a header: logged and skipped
        + b"Content-Length: nope\r\n\r\n{}"  # an unusable length: logged and skipped
        + frame(b'{"jsonrpc": "2.0", "method": "init')  # not JSON: -32700
        + frame(b"[1, 2]")  # a batch: -32600
        + frame(b'{"jsonrpc": "2.0", "id": 2.5, "method": "shutdown"}')  # a float id: -32600
        + frame(b'{"id": 3, "method": "shutdown"}')  # no `jsonrpc`: -32600 with its id
        + message(INITIALIZE)
    )
    initialized = await server.response(1)
    assert "capabilities" in initialized["result"]
    errors = [(m["error"]["code"], m["id"]) for m in server.received if "error" in m]
    assert errors == [(-32700, None), (-32600, None), (-32600, None), (-32600, 3)]
    logs = [m["params"]["message"] for m in server.received if m.get("method") == "window/logMessage"]
    assert len(logs) == 2 and all("cannot frame" in log for log in logs), logs

    await server.send(message({"jsonrpc": "2.0", "id": 4, "method": "shutdown"}))
    assert (await server.response(4))["result"] is None
    assert await server.exit_status() == 0


async def test_exit_without_shutdown_exits_with_status_1():
    server = await Server.start()
    await server.send(message(INITIALIZE))
    await server.response(1)
    assert await server.exit_status() == 1


async def test_a_short_body_at_the_end_of_input_ends_normally():
    server = await Server.start()
    await server.send(message(INITIALIZE) + b"Content-Length: 100\r\n\r\n{\"jsonrpc\"")
    await server.response(1)
    server.process.stdin.close()
    assert await asyncio.wait_for(server.process.wait(), TIMEOUT) == 0
