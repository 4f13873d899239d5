"""Servers for the load benchmark: ``lanterna serve --workers N`` (gunicorn) and nginx.

Each is a child process on a loopback port, started and stopped by its own process id, with
its process tree's CPU time readable from ``/proc`` (to show where the cores went).
"""

from __future__ import annotations

import getpass
import os
import shutil
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

CLK_TCK = os.sysconf("SC_CLK_TCK")


def free_port() -> int:
    """Return a loopback port nothing listens on now."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port: int = s.getsockname()[1]
        return port


def process_tree(pid: int) -> list[int]:
    """``pid`` and all its descendants (Linux ``/proc``)."""
    out, todo = [], [pid]
    while todo:
        p = todo.pop()
        out.append(p)
        try:
            for task in Path(f"/proc/{p}/task").iterdir():
                todo += [int(k) for k in (task / "children").read_text().split()]
        except OSError:
            continue
    return out


def cpu_seconds(pids: list[int]) -> float:
    """User + system CPU seconds used so far by the processes ``pids`` (gone ones count 0)."""
    total = 0
    for pid in pids:
        try:
            fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue
        total += int(fields[11]) + int(fields[12])  # utime, stime (fields 14, 15 of stat)
    return total / CLK_TCK


class Server:
    """A server child process on ``127.0.0.1:port``; stop it with :meth:`stop`."""

    name = "server"

    def __init__(self, argv: list[str], port: int, log: Path) -> None:
        self.port = port
        self.url = f"http://127.0.0.1:{port}"
        self._log = log.open("w")
        self.proc = subprocess.Popen(argv, stdout=self._log, stderr=subprocess.STDOUT)
        deadline = time.monotonic() + 60
        while True:
            try:
                with socket.create_connection(("127.0.0.1", port), timeout=1):
                    break
            except OSError:
                if self.proc.poll() is not None or time.monotonic() > deadline:
                    self.stop()
                    raise RuntimeError(f"{self.name} did not start; see {log}") from None
                time.sleep(0.1)

    def pids(self) -> list[int]:
        """The server's processes (master and workers)."""
        return process_tree(self.proc.pid)

    def stop(self) -> None:
        """Stop the server (SIGTERM, then SIGKILL after 20 s) and wait for it."""
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGTERM)
            try:
                self.proc.wait(20)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()
        self._log.close()


class Gunicorn(Server):
    """``lanterna serve ROOT --workers N [--threads T]``."""

    name = "gunicorn"

    def __init__(self, root: Path, workers: int, threads: int | None, log: Path) -> None:
        port = free_port()
        argv = [str(Path(sys.executable).parent / "lanterna"), "serve", str(root),
                "--port", str(port), "--workers", str(workers)]
        if threads:
            argv += ["--threads", str(threads)]
        super().__init__(argv, port, log)


class WsgiFloor(Server):
    """``floor_app.py`` (a bare WSGI file server) under gunicorn, ``lanterna serve``'s settings."""

    name = "wsgi-floor"

    def __init__(self, root: Path, workers: int, threads: int | None, log: Path) -> None:
        port = free_port()
        argv = [sys.executable, "-m", "gunicorn", "--chdir", str(Path(__file__).parent),
                "-k", "gthread", "--threads", str(threads or 8), "-w", str(workers),
                "--keep-alive", "5", "--backlog", "2048", "--no-control-socket",
                "-b", f"127.0.0.1:{port}", "floor_app:app"]
        os.environ["FLOOR_ROOT"] = str(root)
        super().__init__(argv, port, log)


def nginx_conf(root: Path, port: int, prefix: Path, workers: str = "auto") -> str:
    """An nginx config serving ``root`` at ``/datasets/`` like ``lanterna serve`` does.

    Same headers that matter for tiles (CORS, one hour of caching), sendfile, keep-alive with no
    per-connection request cap (gunicorn has none either), no access log; every path it writes
    (pid, logs, temp folders) is under ``prefix``.
    """
    temp = "\n".join(f"    {kind}_temp_path {prefix}/{kind};"
                     for kind in ("client_body", "proxy", "fastcgi", "uwsgi", "scgi"))
    return f"""user {getpass.getuser()};
worker_processes {workers};
pid {prefix}/nginx.pid;
error_log {prefix}/error.log warn;
daemon off;
events {{ worker_connections 4096; }}
http {{
    access_log off;
    sendfile on;
    tcp_nopush on;
    keepalive_timeout 5s;
    keepalive_requests 1000000;
    types {{ image/jpeg jpg; image/png png; application/json json; }}
{temp}
    server {{
        listen 127.0.0.1:{port};
        location /datasets/ {{
            alias {root}/;
            add_header Access-Control-Allow-Origin * always;
            expires 1h;
        }}
    }}
}}
"""


class Nginx(Server):
    """Debian's nginx serving the same files, with a generated config in a temp folder."""

    name = "nginx"

    def __init__(self, root: Path, prefix: Path, log: Path, workers: str = "auto") -> None:
        binary = shutil.which("nginx") or "/usr/sbin/nginx"
        port = free_port()
        prefix.mkdir(parents=True, exist_ok=True)
        conf = prefix / "nginx.conf"
        conf.write_text(nginx_conf(root, port, prefix, workers))
        super().__init__([binary, "-p", str(prefix), "-e", str(prefix / "error.log"),
                          "-c", str(conf)], port, log)

    def stop(self) -> None:
        """SIGQUIT: nginx's graceful stop (SIGTERM is its fast stop; both end the workers)."""
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGQUIT)
        super().stop()


def version(argv: list[str]) -> str:
    """The first line a tool prints for its version (stdout or stderr)."""
    try:
        done = subprocess.run(argv, capture_output=True, text=True, timeout=10)
    except OSError:
        return "missing"
    return (done.stdout or done.stderr).strip().splitlines()[0]
