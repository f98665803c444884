#!/usr/bin/env python3
# Outsiders must not lock out token holders (issue 45 item 2). Against a server with a token on 127.0.0.1:
# opens N connections without the token from 8 loopback addresses (127.0.0.2–9) — half idle TCP, half
# WebSocket upgrades that never authenticate — holds them, and meanwhile connects as a token holder (the
# header, and the first-message auth) and times the hello. Then waits past the 10-s authentication
# deadline and counts the outsiders' connections the server has closed.
#   lockout.py PORT TOKEN [N]     prints one line per measurement; exits 1 when a token holder is kept out
import base64, os, socket, sys, time

port, token = int(sys.argv[1]), sys.argv[2]
n = int(sys.argv[3]) if len(sys.argv) > 3 else 600

def upgrade(extra=''):
    key = base64.b64encode(os.urandom(16)).decode()
    return (f'GET /live HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n'
            f'Sec-WebSocket-Key: {key}\r\nSec-WebSocket-Version: 13\r\n{extra}\r\n').encode()

def frame(text):  # a masked text frame (client to server)
    data = text.encode(); mask = os.urandom(4)
    head = bytes([0x81]) + (bytes([0x80 | len(data)]) if len(data) < 126 else bytes([0x80 | 126]) + len(data).to_bytes(2, 'big'))
    return head + mask + bytes(b ^ mask[i % 4] for i, b in enumerate(data))

def hello_time(first_message):
    """Seconds from connect to the hello event, or None when the server closes or resets the connection."""
    t0 = time.monotonic()
    try:
        s = socket.create_connection(('127.0.0.1', port), timeout=5)
        s.sendall(upgrade('' if first_message else f'Authorization: Bearer {token}\r\n'))
        buf = b''
        while b'\r\n\r\n' not in buf:
            d = s.recv(4096)
            if not d: return None
            buf += d
        if b' 101 ' not in buf.split(b'\r\n')[0]: return None
        if first_message: s.sendall(frame('{"type": "auth", "token": "%s"}' % token))
        while b'"hello"' not in buf:
            d = s.recv(65536)
            if not d: return None
            buf += d
        s.close()
        return time.monotonic() - t0
    except OSError:
        return None

held = []
refused = 0
for i in range(n):
    src = f'127.0.0.{2 + i % 8}'
    try:
        s = socket.create_connection(('127.0.0.1', port), timeout=2, source_address=(src, 0))
        if i % 2: s.sendall(upgrade())  # upgraded, never authenticated
        held.append(s)
    except OSError:
        refused += 1
time.sleep(1.2)  # the outsiders' connections are now old enough to give way
times = {}
for mode in ('header', 'first message'):
    times[mode] = [hello_time(mode == 'first message') for _ in range(5)]
def still_open():
    alive = 0
    for s in held:
        try:
            s.setblocking(False)
            d = s.recv(65536)
            while d:
                d = s.recv(65536)
            # b'' (EOF): closed by the server
        except BlockingIOError:
            alive += 1  # nothing to read and not closed
        except OSError:
            pass
    return alive
open_then = still_open()
ok = True
for mode, ts in times.items():
    got = [t for t in ts if t is not None]
    print(f'token holder ({mode}): {len(got)} of {len(ts)} connected' + (f', hello after {1000 * max(got):.0f} ms at most' if got else ''))
    ok &= len(got) == len(ts)
print(f'outsiders: {n} connections tried, {refused} refused at connect, {open_then} still open after 1.2 s')
time.sleep(10)
left = still_open()
print(f'outsiders: {left} still open 11 s after connecting (the authentication deadline is 10 s)')
ok &= left == 0
sys.exit(0 if ok else 1)
