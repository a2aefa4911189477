"""A real browser for the tests: headless Chromium driven over the DevTools protocol.

No Python dependency: the system Chromium is started with
``--remote-debugging-pipe`` and spoken to through two pipes, as the protocol
defines them -- the browser reads commands on its file descriptor 3 and
writes answers and events on its file descriptor 4, each message one JSON
object terminated by a NUL byte.  :func:`render` opens one page (a new target,
attached with ``flatten=True`` so every page command carries its
``sessionId``), waits for its load event and returns what a reviewer would
check by hand: console errors, requests that leave the machine, where given
elements are on the first screen, and a screenshot.  :class:`Session` keeps one
browser for several pages (a tab each); :func:`render` is a session of one page.

The browser is always killed (``try``/``finally``) and nothing waits without a
deadline: a browser that does not start, crashes or does not answer in time
is an ``AssertionError`` naming the step (and the tail of its stderr).

Examples
--------
>>> if find_chromium():                                       # doctest: +SKIP
...     r = render("report.html", selectors=("#verdict",))
...     r["boxes"]["#verdict"]["top"], r["console_errors"], r["requests"]
"""
from __future__ import annotations

import base64
import fcntl
import json
import os
import select
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

__all__ = ["find_chromium", "render", "Session", "CANDIDATES", "LOCAL_SCHEMES"]

#: executable names tried by :func:`find_chromium`, in this order
CANDIDATES = ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable")
#: URL schemes that do not leave the machine (everything else is an external request)
LOCAL_SCHEMES = ("file:", "data:", "about:", "blob:")

_FLAGS = ("--headless=new", "--remote-debugging-pipe", "--no-sandbox", "--disable-gpu",
          "--no-first-run", "--no-default-browser-check", "--disable-extensions",
          "--disable-background-networking", "--disable-component-update", "--disable-sync",
          "--disable-default-apps", "--mute-audio", "--hide-scrollbars", "--password-store=basic",
          "--use-mock-keychain")

#: JavaScript returning {selector: box or null} for the selectors in the JSON array %s
_BOXES_JS = """(function (sels) {
  var out = {};
  sels.forEach(function (s) {
    var e = document.querySelector(s);
    if (!e) { out[s] = null; return; }
    var r = e.getBoundingClientRect();
    out[s] = {top: r.top + window.scrollY, left: r.left + window.scrollX,
              width: r.width, height: r.height, text: e.innerText};
  });
  return out;
})(%s)"""


def find_chromium(wait_s: float = 300.0) -> str | None:
    """Path of a Chromium/Chrome executable on ``PATH`` (:data:`CANDIDATES`), else None.

    While the file named by ``$STAND_CHROMIUM_PENDING`` exists (``.ci/run`` installs Chromium
    in the background while the test dependencies install and the kernels compile, and
    removes the file when the install has ended), wait for it, at most ``wait_s`` seconds."""
    pending = os.environ.get("STAND_CHROMIUM_PENDING")
    deadline = time.monotonic() + wait_s
    while pending and os.path.exists(pending) and time.monotonic() < deadline:
        time.sleep(0.5)
    for name in CANDIDATES:
        path = shutil.which(name)
        if path:
            return path
    return None


def _high_pipe() -> tuple:
    """``os.pipe()`` with both ends moved to fds >= 10, so that putting them on the
    child's fds 3 and 4 (and closing the originals) cannot clobber one another."""
    fds = []
    for fd in os.pipe():
        fds.append(fcntl.fcntl(fd, fcntl.F_DUPFD_CLOEXEC, 10))
        os.close(fd)
    return tuple(fds)


class _Browser:
    """One Chromium process and its two protocol pipes (private: use :func:`render`)."""

    def __init__(self, exe: str, profile: str, deadline: float):
        self.deadline = deadline
        self.next_id = 0
        self.buffer = b""
        self.events: list = []
        cmd_r, self.cmd_w = _high_pipe()   # we write commands, the browser reads them on fd 3
        self.msg_r, msg_w = _high_pipe()   # the browser writes messages on fd 4, we read them
        self.stderr_path = Path(profile) / "stderr.txt"
        # a small Python trampoline puts the two pipe ends on fds 3 and 4, closes the
        # originals and execs the browser (no preexec_fn: unsafe with threads, e.g. under
        # pytest-xdist; no shell: dash refuses fd numbers above 9)
        trampoline = ("import os, sys; os.dup2(%d, 3); os.dup2(%d, 4); os.close(%d); os.close(%d); "
                      "os.execv(sys.argv[1], sys.argv[1:])" % (cmd_r, msg_w, cmd_r, msg_w))
        try:
            with open(self.stderr_path, "wb") as err:
                self.proc = subprocess.Popen(
                    [sys.executable, "-c", trampoline, exe, *_FLAGS, f"--user-data-dir={profile}",
                     "about:blank"],
                    stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=err,
                    pass_fds=(cmd_r, msg_w), start_new_session=True)
        finally:
            os.close(cmd_r)
            os.close(msg_w)

    # -- plumbing
    def stderr_tail(self, n: int = 1500) -> str:
        try:
            return self.stderr_path.read_text(errors="replace")[-n:]
        except OSError:
            return ""

    def _fail(self, what: str):
        raise AssertionError(f"headless Chromium: {what}; its stderr ends with:\n{self.stderr_tail()}")

    def send(self, method: str, params: dict | None = None, session: str | None = None) -> int:
        self.next_id += 1
        msg = {"id": self.next_id, "method": method, "params": params or {}}
        if session:
            msg["sessionId"] = session
        data = json.dumps(msg).encode() + b"\0"
        while data:
            try:
                n = os.write(self.cmd_w, data)
            except BrokenPipeError:
                self._fail(f"exited (code {self.proc.poll()}) before the command {method}")
            data = data[n:]
        return self.next_id

    def receive(self, what: str) -> dict:
        """The next message; AssertionError at the deadline or when the browser is gone."""
        while b"\0" not in self.buffer:
            left = self.deadline - time.monotonic()
            if left <= 0:
                self._fail(f"no answer while waiting for {what} (time limit reached)")
            ready, _, _ = select.select([self.msg_r], [], [], left)
            if not ready:
                continue
            chunk = os.read(self.msg_r, 1 << 20)
            if not chunk:
                self._fail(f"closed its pipe (exit code {self.proc.poll()}) while waiting for {what}")
            self.buffer += chunk
        raw, self.buffer = self.buffer.split(b"\0", 1)
        return json.loads(raw)

    def call(self, method: str, params: dict | None = None, session: str | None = None) -> dict:
        """Send a command and return its result; events received meanwhile are kept."""
        want = self.send(method, params, session)
        while True:
            msg = self.receive(method)
            if msg.get("id") == want:
                if "error" in msg:
                    raise AssertionError(f"headless Chromium: {method} failed: {msg['error']}")
                return msg.get("result", {})
            if "method" in msg:
                self.events.append(msg)

    def wait_event(self, method: str, session: str) -> dict:
        """Wait for the event ``method`` of the page ``session``; earlier events are kept."""
        for i, ev in enumerate(self.events):
            if ev.get("method") == method and ev.get("sessionId") == session:
                return self.events.pop(i)
        while True:
            msg = self.receive(method)
            if msg.get("method") == method and msg.get("sessionId") == session:
                return msg
            if "method" in msg:
                self.events.append(msg)

    def close(self) -> None:
        """Ask the browser to close, then kill its process group; never raises."""
        try:
            if self.proc.poll() is None:
                try:
                    self.send("Browser.close")
                except AssertionError:
                    pass
                try:
                    self.proc.wait(timeout=3)
                except subprocess.TimeoutExpired:
                    pass
            if self.proc.poll() is None:
                try:
                    os.killpg(self.proc.pid, 9)     # its own session: the renderers too
                except (ProcessLookupError, PermissionError):
                    self.proc.kill()
                self.proc.wait(timeout=10)
        except Exception:    # pragma: no cover - best effort on the way out
            pass
        finally:
            for fd in (self.cmd_w, self.msg_r):
                try:
                    os.close(fd)
                except OSError:
                    pass


def _console_error(ev: dict) -> str | None:
    """Text of an error-level console message or exception event, else None."""
    m, p = ev.get("method"), ev.get("params", {})
    if m == "Runtime.consoleAPICalled" and p.get("type") in ("error", "assert"):
        args = p.get("args", [])
        return "console." + p["type"] + ": " + " ".join(
            str(a.get("value", a.get("description", ""))) for a in args)
    if m == "Runtime.exceptionThrown":
        d = p.get("exceptionDetails", {})
        return "exception: " + str(d.get("exception", {}).get("description") or d.get("text", ""))
    if m == "Log.entryAdded":
        e = p.get("entry", {})
        if e.get("level") == "error" and e.get("source") != "network":
            return f"log ({e.get('source')}): {e.get('text', '')}"
    return None


class Session:
    """One headless Chromium for several pages: :meth:`render` opens each page in a new tab
    (target) of the same browser and closes the tab afterwards, so a module's pages cost
    one browser start (~1.2 s of CPU and ~4 s on a loaded machine each) instead of one
    each.  Each page's console errors, requests and boxes are its own tab's (events are
    filtered by the tab's session id).  A failed visit (time limit, crash) kills the browser;
    the next :meth:`render` starts a new one.  :meth:`close` kills it (use ``with``).
    """

    def __init__(self):
        self.exe = find_chromium()
        if self.exe is None:
            raise AssertionError("no Chromium on PATH (apt-get install chromium)")
        self.profile = None
        self.browser = None
        self.starts = 0          # browsers started so far

    def _ensure(self, deadline: float):
        if self.browser is not None and self.browser.proc.poll() is not None:
            self.close()         # it exited: start a new one
        if self.browser is None:
            self.profile = tempfile.mkdtemp(prefix="stand-chromium-")
            self.browser = _Browser(self.exe, self.profile, deadline)
            self.starts += 1
        self.browser.deadline = deadline
        return self.browser

    def render(self, html_path, width: int = 1280, height: int = 900, timeout: float = 30,
               selectors=("#verdict",), full_page: bool = False) -> dict:
        """As :func:`render` (same arguments and result), in a new tab of this session's
        browser; ``timeout`` counts from this call (a browser start included when one is
        needed)."""
        path = Path(html_path).resolve()
        if not path.is_file():
            raise AssertionError(f"render: {path} does not exist")
        browser = self._ensure(time.monotonic() + timeout)
        try:
            return _visit(browser, path, width, height, selectors, full_page)
        except BaseException:
            self.close()         # a hung or broken browser is never reused
            raise

    def close(self) -> None:
        """Kill the browser (if any) and remove its profile; never raises."""
        if self.browser is not None:
            self.browser.close()
            self.browser = None
        if self.profile is not None:
            shutil.rmtree(self.profile, ignore_errors=True)
            self.profile = None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False


def _visit(browser: _Browser, path: Path, width, height, selectors, full_page) -> dict:
    """Open ``path`` in a new tab of ``browser`` and collect what :func:`render` returns."""
    target = browser.call("Target.createTarget", {"url": "about:blank"})["targetId"]
    sid = browser.call("Target.attachToTarget", {"targetId": target, "flatten": True})["sessionId"]
    for domain in ("Runtime", "Log", "Network", "Page"):
        browser.call(f"{domain}.enable", session=sid)
    browser.call("Emulation.setDeviceMetricsOverride",
                 {"width": width, "height": height, "deviceScaleFactor": 1, "mobile": False},
                 session=sid)
    nav = browser.call("Page.navigate", {"url": path.as_uri()}, session=sid)
    if nav.get("errorText"):
        raise AssertionError(f"render: {path} did not load: {nav['errorText']}")
    browser.wait_event("Page.loadEventFired", sid)
    boxes = browser.call("Runtime.evaluate", {
        "expression": _BOXES_JS % json.dumps(list(selectors)), "returnByValue": True},
        session=sid)["result"].get("value", {})
    title = browser.call("Runtime.evaluate", {"expression": "document.title",
                                              "returnByValue": True}, session=sid)
    shot = {"format": "png"}
    if full_page:
        size = browser.call("Page.getLayoutMetrics", session=sid)["cssContentSize"]
        shot.update(captureBeyondViewport=True, clip={
            "x": 0, "y": 0, "width": size["width"], "height": size["height"], "scale": 1})
    png = base64.b64decode(browser.call("Page.captureScreenshot", shot, session=sid)["data"])
    browser.call("Target.closeTarget", {"targetId": target})   # the tab goes, and its events
    events = [ev for ev in browser.events if ev.get("sessionId") == sid]
    browser.events = [ev for ev in browser.events if ev.get("sessionId") != sid]
    console, network, requests = [], [], []
    for ev in events:
        text = _console_error(ev)
        if text is not None:
            console.append(text)
        p = ev.get("params", {})
        if ev.get("method") == "Log.entryAdded" and p.get("entry", {}).get("source") == "network" \
                and p["entry"].get("level") == "error":
            network.append(f"{p['entry'].get('url', '')}: {p['entry'].get('text', '')}")
        if ev.get("method") in ("Network.requestWillBeSent", "Network.webSocketCreated"):
            url = p.get("request", {}).get("url") if "request" in p else p.get("url")
            if url and not url.startswith(LOCAL_SCHEMES) and url not in requests:
                requests.append(url)
    return {"console_errors": console, "network_errors": network, "requests": requests,
            "boxes": boxes, "screenshot_png": png, "title": title["result"].get("value", "")}


def render(html_path, width: int = 1280, height: int = 900, timeout: float = 30,
           selectors=("#verdict",), full_page: bool = False) -> dict:
    """Open a local HTML file in headless Chromium and report what it did.

    Parameters
    ----------
    html_path : str or os.PathLike
        The page (opened as a ``file://`` URL).
    width, height : int
        Viewport in CSS pixels (device scale factor 1): the "first screen".
    timeout : float
        Limit for the whole visit [s], start of the browser included.
    selectors : sequence of str
        CSS selectors whose first match is measured (``boxes``).
    full_page : bool
        Screenshot of the whole page instead of the viewport.

    Returns
    -------
    dict
        ``console_errors`` (list of str: ``console.error``/``console.assert``
        calls, uncaught exceptions, error-level log entries other than network
        ones), ``network_errors`` (list of str: resources that failed to load,
        from the log's network entries), ``requests`` (list of str: URLs
        requested with a scheme other than :data:`LOCAL_SCHEMES`, i.e. that
        would leave the machine), ``boxes`` (``{selector: {"top", "left",
        "width", "height", "text"} or None}``, CSS px from the top-left of the
        page, ``text`` the element's ``innerText``), ``screenshot_png`` (bytes),
        ``title`` (str).

    Raises
    ------
    AssertionError
        No Chromium on ``PATH``, the page does not exist or fails to load, or
        the browser does not start/answer within ``timeout``.
    """
    with Session() as session:      # its own browser, killed on the way out
        return session.render(html_path, width, height, timeout, selectors, full_page)
