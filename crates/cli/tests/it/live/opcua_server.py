#!/usr/bin/env python3
"""OPC UA test server of crates/cli/tests/it/live/mod.rs, on asyncua (PyPI): a controller that plays a
thermal campaign (examples/thermal) into its temperature nodes and takes the offsets that
`trueaxis live` writes back.

Nodes (namespace 2, urn:trueaxis:test): vmc3.T_<sensor> (Double, degC), vmc3.Run (String, the
campaign's run), vmc3.Offset_X/Y/Z (Double, mm, writable). Every row is written with the source
timestamp 2020-01-01T00:00:00Z + the campaign time (each run 1 h after the end of the one before),
paced at --speed times real time. The offsets written by the client are recorded twice: by the
server (every Write service call, with its source timestamp) and by an asyncua client subscribed
to the offset nodes (trigger StatusValueTimestamp, so that a repeated value is still reported).

Faults: --outage-after N stops the server after N rows (once the offsets of row N-1 have been
written) for --outage-s wall seconds and starts a new one on the same port (the rows due meanwhile are lost); repeat both for several outages. The
new server holds the row due at its start and waits (at most --rejoin-wait s) for the client's
first write before it plays on, as at the start. --jump-row N adds --jump degC to --jump-sensor in
row N.

Prints one JSON document on stdout at the end: {"base": unix s, "rows": [[run, unix s, values as
written...], ...], "restarts": [unix s of the row each new server started with, ...],
"server": {"X": [[unix s, mm], ...], ...}, "client": {...}}.
"""

import argparse
import asyncio
import csv
import datetime
import json
import logging

from asyncua import Client, Server, ua
from asyncua.common.callback import CallbackType

BASE = datetime.datetime(2020, 1, 1, tzinfo=datetime.timezone.utc)
AXES = ["X", "Y", "Z"]


def unix(ts):
    return (ts - datetime.datetime(1970, 1, 1, tzinfo=datetime.timezone.utc)).total_seconds()


def read_campaign(path, sensors):
    rows = []
    with open(path) as f:
        for row in csv.DictReader(line for line in f if not line.startswith("#")):
            rows.append((row["run"], float(row["t"]), [float(row[s]) for s in sensors]))
    # one clock: each run starts 1 h after the end of the one before
    out, offset, last_run, last_t = [], 0.0, None, 0.0
    for run, t, values in rows:
        if last_run is not None and run != last_run:
            offset += last_t + 3600.0
        out.append((run, offset + t, values))
        last_run, last_t = run, t
    return out


class Recorder:
    """The values written to or seen on the offset nodes, by axis."""

    def __init__(self):
        self.values = {a: [] for a in AXES}
        self.node_axis = {}

    def record(self, node_id, dv):
        axis = self.node_axis.get(node_id.to_string())
        if axis is not None and dv.SourceTimestamp is not None:
            self.values[axis].append([unix(dv.SourceTimestamp), dv.Value.Value])


async def start_server(port, sensors, recorder, first):
    """A server whose nodes hold `first` (run, campaign s, values) before it accepts clients."""
    server = Server()
    await server.init()
    server.set_endpoint(f"opc.tcp://127.0.0.1:{port}/trueaxis/")
    server.set_security_policy([ua.SecurityPolicyType.NoSecurity])
    idx = await server.register_namespace("urn:trueaxis:test")
    machine = await server.nodes.objects.add_object(ua.NodeId("vmc3", idx), "vmc3")
    nodes = {}
    for s in sensors:
        name = "T_" + s[2:]
        nodes[s] = await machine.add_variable(ua.NodeId("vmc3." + name, idx), name, 20.0, ua.VariantType.Double)
    nodes["run"] = await machine.add_variable(ua.NodeId("vmc3.Run", idx), "Run", "", ua.VariantType.String)
    for a in AXES:
        node = await machine.add_variable(ua.NodeId(f"vmc3.Offset_{a}", idx), f"Offset_{a}", 0.0, ua.VariantType.Double)
        await node.set_writable()
        recorder.node_axis[node.nodeid.to_string()] = a

    async def on_write(event, _dispatcher):
        if event.is_external:
            for wv in event.request_params.NodesToWrite:
                recorder.record(wv.NodeId, wv.Value)

    server.subscribe_server_callback(CallbackType.PostWrite, on_write)
    run, t, values = first
    ts = BASE + datetime.timedelta(seconds=t)
    await write(nodes["run"], run, ts, ua.VariantType.String)
    for s, v in zip(sensors, values):
        await write(nodes[s], v, ts, ua.VariantType.Double)
    await server.start()
    return server, nodes


class ClientHandler:
    def __init__(self, recorder):
        self.recorder = recorder

    def datachange_notification(self, node, val, data):
        self.recorder.record(node.nodeid, data.monitored_item.Value)


async def subscribe_client(port, recorder):
    client = Client(f"opc.tcp://127.0.0.1:{port}/trueaxis/")
    await client.connect()
    idx = await client.get_namespace_index("urn:trueaxis:test")
    nodes = [client.get_node(ua.NodeId(f"vmc3.Offset_{a}", idx)) for a in AXES]
    for n, a in zip(nodes, AXES):
        recorder.node_axis[n.nodeid.to_string()] = a
    sub = await client.create_subscription(20, ClientHandler(recorder))
    trigger = ua.DataChangeFilter(Trigger=ua.DataChangeTrigger.StatusValueTimestamp)
    await sub._subscribe(nodes, ua.AttributeIds.Value, trigger, queuesize=100000, sampling_interval=0)
    return client


async def write(node, value, ts, variant):
    await node.write_value(ua.DataValue(ua.Variant(value, variant), SourceTimestamp=ts, ServerTimestamp=ts))


# Seconds a stop of the server or the client may take.
STOP_S = 5.0


async def main():
    p = argparse.ArgumentParser()
    p.add_argument("--port", type=int, required=True)
    p.add_argument("--campaign", required=True)
    p.add_argument("--sensors", default="T:p1,T:p5")
    p.add_argument("--speed", type=float, default=1000.0)
    p.add_argument("--rows", type=int, default=0, help="play only the first N rows (0: all)")
    p.add_argument("--start-wait", type=float, default=20.0, help="wall s to wait for the client's subscription")
    p.add_argument("--end-wait", type=float, default=2.0)
    p.add_argument("--outage-after", type=int, action="append", default=[])
    p.add_argument("--outage-s", type=float, action="append", default=[])
    p.add_argument("--rejoin-wait", type=float, default=30.0, help="wall s to wait for the client after a restart")
    p.add_argument("--jump-row", type=int, default=-1)
    p.add_argument("--jump-sensor", default="T:p1")
    p.add_argument("--jump", type=float, default=200.0)
    p.add_argument("--client", action="store_true", help="also record through an asyncua client subscription")
    a = p.parse_args()
    if len(a.outage_after) != len(a.outage_s):
        p.error("give one --outage-s per --outage-after")
    outages = dict(zip(a.outage_after, a.outage_s))
    logging.basicConfig(level=logging.ERROR)
    sensors = a.sensors.split(",")
    rows = read_campaign(a.campaign, sensors)
    if a.rows:
        rows = rows[: a.rows]
    by_server, by_client = Recorder(), Recorder()
    server, nodes = await start_server(a.port, sensors, by_server, rows[0])
    client = await subscribe_client(a.port, by_client) if a.client else None
    # the first row, then wait until trueaxis live has subscribed (its first write) or the start wait ends
    played, last_run, previous, resume_at, restarts = [], rows[0][0], None, None, []
    for i, (run, t, values) in enumerate(rows):
        if i in outages:
            # the outage starts once the offsets of the last row played have come (at most 10 s)
            await wait_for_offsets(by_server, played[-1][1] if played else None, 10.0)
            await stop(server)
            await asyncio.sleep(outages[i])
            # the rows due while the server was down are lost; the new server starts with the next
            resume_at = previous + outages[i] * a.speed
            following = next((r for r in rows[i:] if r[1] >= resume_at), rows[-1])
            recorded = sum(len(v) for v in by_server.values.values())
            server, nodes = await start_server(a.port, sensors, by_server, following)
            restarts.append(unix(BASE + datetime.timedelta(seconds=following[1])))
            last_run, previous = following[0], resume_at
            # the client back (its first write on the new server), as at the start
            for _ in range(int(a.rejoin_wait / 0.05)):
                if sum(len(v) for v in by_server.values.values()) > recorded:
                    break
                await asyncio.sleep(0.05)
        if resume_at is not None and t < resume_at:
            continue
        if previous is not None and i not in outages:
            await asyncio.sleep(max(0.0, (t - previous) / a.speed))
        previous = t
        ts = BASE + datetime.timedelta(seconds=t)
        if run != last_run:
            await write(nodes["run"], run, ts, ua.VariantType.String)
            await asyncio.sleep(0.05)
            last_run = run
        written = [v + a.jump if i == a.jump_row and s == a.jump_sensor else v for s, v in zip(sensors, values)]
        for s, v in zip(sensors, written):
            await write(nodes[s], v, ts, ua.VariantType.Double)
        played.append([run, unix(ts)] + written)
        if i == 0:
            # wait until trueaxis live has subscribed and written its first offsets
            for _ in range(int(a.start_wait / 0.05)):
                if any(by_server.values.values()):
                    break
                await asyncio.sleep(0.05)
    # wait for the offsets of the last row (at most 60 s), then --end-wait more
    await wait_for_offsets(by_server, played[-1][1] if played else None, 60.0)
    await asyncio.sleep(a.end_wait)
    # the record first: a stop that waits on a connection the test has not yet closed must not hold it
    print(json.dumps({"base": unix(BASE), "rows": played, "restarts": restarts, "server": by_server.values, "client": by_client.values}), flush=True)
    if client is not None:
        await asyncio.wait_for(client.disconnect(), STOP_S)
    await stop(server)


async def wait_for_offsets(recorder, unix_s, limit_s):
    """Waits (at most limit_s) until an offset of Z with the source timestamp unix_s was written."""
    for _ in range(int(limit_s / 0.05)):
        if unix_s is None or any(t == unix_s for t, _ in recorder.values["Z"]):
            return
        await asyncio.sleep(0.05)


async def stop(server):
    """Stops the server: its listening socket first, so that a client reconnecting at once (trueaxis
    live does) cannot open a session on a server that is going away; then the rest, bounded, since
    asyncua 2.1's stop waits for its connections to close, which a running client may never do."""
    listening = getattr(getattr(server, "bserver", None), "_server", None)
    if listening is not None:
        listening.close()
    try:
        await asyncio.wait_for(server.stop(), STOP_S)
    except asyncio.TimeoutError:
        logging.error("the server did not stop within %s s; its sockets are closed", STOP_S)


if __name__ == "__main__":
    asyncio.run(main())
