# pvserver with a client (docs/paraview.md, "pvserver"): the test starts `mpirun -np N pvserver`
# on a free port, connects to it as a ParaView client would (paraview.simple's Connect), loads the
# plugin on both sides, and checks what a user of the GUI would see:
# - the server runs N ranks;
# - the CAD reader on the server: a file that crashes OpenCASCADE is an empty output and the
#   server carries on (its worker process); then product.step reads (1,564 triangles, 72 edges);
# - the WireFur view rendered on the server (remote rendering forced: RemoteRenderThreshold 0)
#   over N ranks and shown by the client is the one-rank picture of view_mpi_test.py (RGB RMS
#   <= 1e-3, the same fragments and error bound; the fixture paraview.view.np1 writes it).
# The server is stopped at the end, whatever happened. Prints "all checks passed".
# Usage (under Xvfb, by a Python that has ParaView's modules):
#   python3 pvserver_test.py PLUGIN.so OUT_DIR SOURCE_DIR MPIRUN PVSERVER [N]
import os
import signal
import socket
import subprocess
import sys
import time

plugin, out, source, mpirun, pvserver = sys.argv[1:6]
ranks = int(sys.argv[6]) if len(sys.argv) > 6 else 2
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
failures = []


def check(what, ok, detail=""):
    print(f"{what}: {'ok' if ok else 'FAILED'} {detail}", flush=True)
    if not ok:
        failures.append(what)


def free_port():
    with socket.socket() as s:
        s.bind(("localhost", 0))
        return s.getsockname()[1]


port = free_port()
log_path = os.path.join(out, "pvserver.log")
os.makedirs(out, exist_ok=True)
log = open(log_path, "w")
# (pvpython is itself an MPI singleton: its OpenMPI variables would make mpirun think it is nested.)
env = {k: v for k, v in os.environ.items() if not k.startswith(("OMPI_", "PMIX_", "OPAL_", "PRTE_"))}
server = subprocess.Popen([mpirun, "--allow-run-as-root", "--oversubscribe", "-np", str(ranks), pvserver,
                           f"--server-port={port}"], stdout=log, stderr=subprocess.STDOUT, start_new_session=True,
                          env=env)


def stop_server():
    """Disconnects (a pvserver without --multi-clients then ends), and makes sure no rank is left:
    a rank may keep spinning in MPI once rank 0 has gone."""
    try:
        from paraview.simple import Disconnect
        Disconnect()
    except Exception:
        pass
    try:
        server.wait(timeout=3)
    except Exception:
        pass
    for sig in (signal.SIGTERM, signal.SIGKILL):
        try:
            os.killpg(server.pid, sig)
        except Exception:
            pass
        subprocess.run(["pkill", "-" + str(int(sig)), "-f", f"pvserver --server-port={port}"], check=False)
        time.sleep(0.5)
    try:
        server.wait(timeout=10)
    except Exception:
        pass


def server_log():
    with open(log_path) as f:
        return f.read()


def finish():
    stop_server()
    left = subprocess.run(["pgrep", "-f", f"pvserver --server-port={port}"], capture_output=True, text=True).stdout.split()
    check("no server process left", not left, " ".join(left))
    errors = [line for line in server_log().splitlines() if "ERR|" in line]
    # The one error the server may print: the crashing file's, from the reader.
    unexpected = [e for e in errors if "OpenCASCADE crashed reading this file" not in e
                  and "Could not receive tag" not in e and "Some error in socket processing" not in e]
    check("the server logged no other error", not unexpected, "\n".join(unexpected[:5]))
    print("FAILED: " + ", ".join(failures) if failures else "all checks passed", flush=True)
    os._exit(1 if failures else 0)


try:
    deadline = time.time() + 120
    while "Accepting connection" not in server_log():
        if server.poll() is not None or time.time() > deadline:
            check("pvserver started", False, f"(exit {server.poll()}) " + server_log()[-2000:])
            finish()
        time.sleep(0.2)

    from paraview import servermanager as sm
    from paraview.simple import *
    import view_mpi_test as scene

    Connect("localhost", port)
    LoadPlugin(plugin, remote=False, ns=globals())
    LoadPlugin(plugin, remote=True, ns=globals())
    check(f"the server runs {ranks} ranks", sm.ActiveConnection.GetNumberOfDataPartitions() == ranks,
          str(sm.ActiveConnection.GetNumberOfDataPartitions()))

    bad = WireFurCADReader(FileName=os.path.join(source, "tests", "apps", "cad_regressions",
                                                 "step_segv_cartesianpoint.step"))
    bad.UpdatePipeline()
    check("a file that crashes OpenCASCADE: empty output", bad.GetDataInformation().GetNumberOfCells() == 0)
    check("the server lives on", server.poll() is None)
    good = WireFurCADReader(FileName=os.path.join(source, "data", "cad", "product.step"))
    good.UpdatePipeline()
    counts = (good.GetDataInformation().GetNumberOfCells(), OutputPort(good, 1).GetDataInformation().GetNumberOfCells())
    check("then product.step reads (1,564 triangles, 72 edges)", counts == (1564, 72), str(counts))
    Delete(bad)
    Delete(good)

    view = scene.build_scene()
    view.RemoteRenderThreshold = 0  # render on the server, whatever the data's size
    Render(view)
    path = os.path.join(out, "view_pvserver_np%d.png" % ranks)
    SaveScreenshot(path, view, ImageResolution=[scene.W, scene.H], TransparentBackground=0)
    info = scene.figures(view)
    print("figures", info, flush=True)
    check("rendered on the server (a composite over its ranks)", info["CompositeSeconds"] > 0 if ranks > 1 else True,
          str(info["CompositeSeconds"]))
    img = scene.load(path)
    scene.compare(img, info, out, "through pvserver on %d ranks" % ranks, check)
except Exception as e:
    check("the client ran to its end", False, repr(e))
finish()
