"""The VS Code extension in the real VS Code UI: code-server (VS Code for the Web) in Debian's
headless Chromium, driven by Playwright. The extension is the .vsix built by vsce, installed with
`code-server --install-extension`; every check is made on what the workbench shows.

Usage: ui_test.py CODE_SERVER_DIR GLOC_VSIX GLOC_BIN ARTIFACTS_DIR
A failed check saves a screenshot in ARTIFACTS_DIR and exits 1.
"""

import json
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from playwright.sync_api import Page, sync_playwright

REPO = Path(__file__).resolve().parents[3]
CHROMIUM = "/usr/bin/chromium"


class Failure(Exception):
    pass


def wait_for(what, probe, timeout=30.0, interval=0.25):
    """Polls `probe` until it returns a true value, else fails naming `what`."""
    deadline = time.monotonic() + timeout
    last = None
    while time.monotonic() < deadline:
        try:
            last = probe()
        except Exception as error:  # the workbench re-renders under us: try again
            last = error
        if last and not isinstance(last, Exception):
            return last
        time.sleep(interval)
    raise Failure(f"timed out after {timeout:.0f} s waiting for {what} (last seen: {last!r})")


class Workbench:
    def __init__(self, page: Page, artifacts: Path):
        self.page = page
        self.artifacts = artifacts
        self.step = "start"

    def shot(self, name):
        self.artifacts.mkdir(parents=True, exist_ok=True)
        path = self.artifacts / f"{name}.png"
        self.page.screenshot(path=str(path))
        return path

    def command(self, title):
        """Runs a command by its title from the command palette."""
        box = self.page.locator(".quick-input-widget .quick-input-box input")
        for attempt in range(5):
            self.page.keyboard.press("F1")
            try:
                # Generous: on a loaded 2-core machine the palette took over 4 s to show.
                box.wait_for(state="visible", timeout=8_000)
                break
            except Exception:
                # Focus inside a webview (the SVG preview) or on a notification keeps F1
                # from the workbench: give the focus back to the workbench and try again.
                self.page.keyboard.press("Escape")
                self.page.locator(".part.sidebar .pane-body").first.click(position={"x": 150, "y": 300})
        box.wait_for(state="visible", timeout=8_000)
        box.fill(">" + title)

        def exact_row():
            for row in self.page.locator(".quick-input-widget .quick-input-list .monaco-list-row").all():
                label = (row.get_attribute("aria-label") or "").lower()
                if label == title.lower() or label.startswith(title.lower() + ","):
                    return row
            return None

        wait_for(f"the command palette to offer {title!r}", exact_row, timeout=10).click()

    def open_file(self, name):
        self.command("Go to File...")
        box = self.page.locator(".quick-input-widget .quick-input-box input")
        box.fill(name)

        def offered():
            row = self.page.locator(".quick-input-widget .quick-input-list .monaco-list-row").first
            return name in (row.get_attribute("aria-label") or "")

        wait_for(f"quick open to offer {name}", offered, timeout=15)
        self.page.keyboard.press("Enter")
        wait_for(f"{name} in the active tab", lambda: name in self.active_tab())
        self.page.locator(".editor-group-container.active .monaco-editor .view-lines").first.wait_for()

    def active_tab(self):
        tab = self.page.locator(".editor-group-container.active .tab.active")
        return tab.first.get_attribute("aria-label") or "" if tab.count() else ""

    def tabs(self):
        return [t.get_attribute("aria-label") or "" for t in self.page.locator(".tabs-container .tab").all()]

    def goto_line(self, line, column=1):
        self.command("Go to Line/Column...")
        self.page.keyboard.type(f"{line}:{column}")
        self.page.keyboard.press("Enter")

    def set_user_setting(self, key, value):
        """Sets a string setting in the Settings editor's User tab, as a user would."""
        self.command("Preferences: Open User Settings")
        self.page.locator(".settings-editor").wait_for(timeout=20_000)
        self.page.keyboard.type(key)
        field = self.page.locator(
            f'.settings-editor .setting-item-contents[data-key="{key}"] input, '
            f'.settings-editor .setting-item-contents:has-text("{key.split(".")[-1].capitalize()}") .setting-item-control input'
        ).first
        field.wait_for(timeout=20_000)
        field.fill(value)
        field.press("Tab")
        self.command("View: Close Editor")

    def toasts(self):
        return [
            t.inner_text()
            for t in self.page.locator(".notifications-toasts .notification-toast .notification-list-item-message").all()
        ]

    def clear_toasts(self):
        self.command("Notifications: Clear All Notifications")
        wait_for("the notifications to clear", lambda: not self.toasts(), timeout=10)

    def line_text(self, line_number):
        """The rendered text of one editor line (the line must be in view)."""
        lines = self.page.locator(".editor-group-container.active .monaco-editor .view-line")
        tops = []
        for line in lines.all():
            style = line.get_attribute("style") or ""
            top = re.search(r"top:\s*(\d+)px", style)
            tops.append((int(top.group(1)) if top else 0, line))
        tops.sort(key=lambda pair: pair[0])
        return tops[line_number - 1][1] if line_number <= len(tops) else None

    def call_stack_frames(self):
        rows = self.page.locator(".debug-call-stack .monaco-list-row .stack-frame")
        return [row.inner_text().replace("\n", " ") for row in rows.all()]

    def variables_rows(self):
        rows = self.page.locator(".debug-pane .debug-variables .monaco-list-row")
        return [row.inner_text().replace("\n", " ") for row in rows.all()]


def top_frame_cycle(bench: Workbench):
    for frame in bench.call_stack_frames():
        found = re.search(r"cycle (\d+)", frame)
        if found:
            return int(found.group(1))
    return None


def start_code_server(code_server: Path, user_data: Path, extensions: Path, workspace: Path, env):
    log = open(user_data / "code-server.log", "w")
    process = subprocess.Popen(
        [
            "node",
            str(code_server / "out/node/entry.js"),
            "--auth",
            "none",
            "--bind-addr",
            "127.0.0.1:0",
            "--user-data-dir",
            str(user_data),
            "--extensions-dir",
            str(extensions),
            "--disable-telemetry",
            "--disable-update-check",
            "--disable-workspace-trust",
            "--disable-getting-started-override",
            str(workspace),
        ],
        stdout=subprocess.PIPE,
        stderr=log,
        env=env,
        text=True,
        start_new_session=True,
    )
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline:
        line = process.stdout.readline()
        if not line:
            raise Failure("code-server exited before listening; see " + str(user_data / "code-server.log"))
        found = re.search(r"HTTP server listening on (http://127\.0\.0\.1:\d+/)", line)
        if found:
            return process, found.group(1)
    raise Failure("code-server did not say where it listens within 60 s")


def write_settings(user_data: Path, settings):
    folder = user_data / "User"
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "settings.json").write_text(json.dumps(settings, indent=2))


def main():
    code_server, vsix, gloc_bin, artifacts = (Path(arg).resolve() for arg in sys.argv[1:5])
    started = time.monotonic()
    scratch = Path(tempfile.mkdtemp(prefix="gloc-vscode-ui-"))
    user_data, extensions, workspace, home, tmp = (
        scratch / name for name in ("user-data", "extensions", "workspace", "home", "tmp")
    )
    for folder in (user_data, extensions, workspace, home, tmp):
        folder.mkdir()
    for name in ("fig3.gbas", "thermocline.gbas", "fig2.gloc", "fig2.mi"):
        shutil.copy(REPO / "examples" / name, workspace / name)
    original_fig3 = (workspace / "fig3.gbas").read_text()

    # The login shell the extension host takes its PATH from: a plain profile, no gloc on it.
    env = {
        "HOME": str(home),
        "PATH": "/usr/local/bin:/usr/bin:/bin",
        "SHELL": "/bin/bash",
        "TMPDIR": str(tmp),
        "LANG": "C.UTF-8",
    }
    subprocess.run(
        [
            "node",
            str(code_server / "out/node/entry.js"),
            "--user-data-dir",
            str(user_data),
            "--extensions-dir",
            str(extensions),
            "--install-extension",
            str(vsix),
        ],
        check=True,
        env=env,
        stdout=subprocess.DEVNULL,
    )
    base_settings = {
        "files.autoSave": "off",
        "workbench.startupEditor": "none",
        "workbench.tips.enabled": False,
        "workbench.enableExperiments": False,
        "extensions.ignoreRecommendations": True,
        "extensions.autoCheckUpdates": False,
        "extensions.autoUpdate": False,
        "telemetry.telemetryLevel": "off",
        "security.workspace.trust.enabled": False,
        "window.commandCenter": False,
        "editor.hover.delay": 100,
        "debug.toolBarLocation": "docked",
    }
    # gloc.path in the *User* settings: a remote window (code-server is one) used to drop it at
    # the first settings re-read, which F5 triggers.
    write_settings(user_data, {**base_settings, "gloc.path": str(gloc_bin)})

    server, url = start_code_server(code_server, user_data, extensions, workspace, env)
    failed = None
    try:
        with sync_playwright() as playwright:
            # A missing chromium fails here, and fails the run.
            browser = playwright.chromium.launch(executable_path=CHROMIUM, args=["--no-sandbox"])
            page = browser.new_page(viewport={"width": 1400, "height": 900})
            bench = Workbench(page, artifacts)
            try:
                run_checks(bench, url, workspace, gloc_bin, home, tmp, original_fig3)
            except Exception as error:  # noqa: BLE001 - every failure gets its screenshot
                failed = error
                shot = bench.shot(f"failed-{bench.step}")
                print(f"FAILED at step {bench.step!r}: {error}\nscreenshot: {shot}", file=sys.stderr)
            finally:
                browser.close()
    finally:
        os.killpg(server.pid, signal.SIGTERM)
        server.wait(timeout=30)
    if failed:
        print("code-server log: " + str(user_data / "code-server.log"), file=sys.stderr)
        sys.exit(1)
    shutil.rmtree(scratch, ignore_errors=True)
    print(f"vscode ui: all checks passed in {time.monotonic() - started:.0f} s")


def check(condition, message):
    if not condition:
        raise Failure(message)


def run_checks(bench, url, workspace, gloc_bin, home, tmp, original_fig3):
    page = bench.page
    bench.step = "load"
    page.goto(url + "?folder=" + str(workspace))
    page.locator(".monaco-workbench").wait_for(timeout=60_000)
    wait_for("the explorer to list fig3.gbas", lambda: page.get_by_text("fig3.gbas").count() > 0, timeout=60)

    bench.step = "activation"
    bench.open_file("fig3.gbas")
    mode = page.locator("#status\\.editor\\.mode")
    wait_for("the GBASIC language mode", lambda: "GBASIC" in mode.inner_text(), timeout=20)

    bench.step = "highlighting"
    # `if m_depth > 15.0 then`: the keyword, the sensor and the number are different tokens, each
    # with its own colour class from the grammar (and the server's semantic tokens).
    def coloured_line_2():
        line = bench.line_text(2)
        spans = line.locator("span > span").all()
        classes = {span.get_attribute("class") for span in spans if span.inner_text().strip()}
        return len(classes) >= 3 and classes

    wait_for("line 2 coloured in at least three token classes", coloured_line_2)

    bench.step = "diagnostics"
    # A typed error: a squiggle in the editor and an entry in Problems (autosave is off, so the
    # file on disk is untouched).
    bench.goto_line(17, 1)
    page.keyboard.press("End")
    page.keyboard.press("Enter")
    page.keyboard.type("x = = 1")
    wait_for("an error squiggle", lambda: page.locator(".monaco-editor .squiggly-error").count() > 0)
    bench.command("View: Focus Problems (Errors, Warnings, Infos)")

    def problem_rows():
        rows = page.locator(".part.panel .monaco-list-row").all()
        texts = [row.inner_text().replace("\n", " ") for row in rows]
        return [text for text in texts if re.search(r"E\d{4}", text)] or None

    problems = wait_for("an E-coded entry in Problems", problem_rows)
    check(any("Ln 18" in text for text in problems), f"the Problems entry is not on line 18: {problems}")

    bench.step = "completion"
    bench.open_file("fig3.gbas")
    page.keyboard.press("Control+a")
    page.keyboard.press("Control+End")
    page.keyboard.press("Enter")
    page.keyboard.type("if m_dep")  # an expression: read-only sensors such as m_depth are offered
    page.keyboard.press("Control+Space")

    def suggestions():
        rows = page.locator(".suggest-widget.visible .monaco-list-row").all()
        labels = [row.get_attribute("aria-label") or "" for row in rows]
        return [label for label in labels if "m_depth" in label] or None

    wait_for("m_depth among the completions", suggestions)
    page.keyboard.press("Escape")
    bench.command("File: Revert File")
    wait_for("the squiggle to go once the file is reverted", lambda: page.locator(".monaco-editor .squiggly-error").count() == 0)

    bench.step = "hover"
    bench.goto_line(2, 5)  # inside `m_depth`
    bench.command("Show or Focus Hover")

    def hover_text():
        hover = page.locator(".monaco-hover:not(.hidden) .hover-contents")
        text = " ".join(h.inner_text() for h in hover.all())
        return "m_depth" in text and text

    hover = wait_for("a hover naming m_depth", hover_text)
    check(re.search(r"\bm\b|metre|meter", hover) is not None, f"the m_depth hover gives no unit: {hover!r}")
    page.keyboard.press("Escape")

    bench.step = "show-compiled"
    bench.command("GLOC: Show compiled GLOC")
    wait_for("the compiled GLOC tab", lambda: any("fig3.gbas.gloc" in tab for tab in bench.tabs()), timeout=20)

    def compiled_text():
        editors = page.locator(".editor-group-container .monaco-editor .view-lines").all()
        texts = [e.inner_text() for e in editors]
        return any("goto" in text or "jmp" in text or "yield" in text for text in texts[1:]) and texts

    wait_for("GLOC instructions in the compiled view", compiled_text, timeout=20)
    bench.command("View: Close All Editor Groups")

    bench.step = "run-mission"
    bench.open_file("fig3.gbas")
    bench.command("GLOC: Run mission in simulator")
    wait_for("the flight profile fig3.svg opened", lambda: any("fig3.svg" in tab for tab in bench.tabs()), timeout=120)
    leftovers = [p.name for p in tmp.iterdir() if p.name.startswith("gloc-run-")]
    check(not leftovers, f"Run mission left temp folders behind: {leftovers}")
    bench.command("View: Close All Editor Groups")

    bench.step = "f5-stop-on-entry"
    bench.open_file("fig3.gbas")
    page.keyboard.press("F5")
    wait_for("the stop on entry at cycle 0", lambda: top_frame_cycle(bench) == 0, timeout=60)

    bench.step = "scopes"
    bench.command("Run and Debug: Focus on Variables View")
    wait_for(
        "the four scopes",
        lambda: all(any(row.startswith(scope) for row in bench.variables_rows()) for scope in ("Variables", "Registers", "Sensors", "Vehicle")),
    )

    bench.step = "step-over"
    page.keyboard.press("F10")
    wait_for("Step Over to reach cycle 1", lambda: top_frame_cycle(bench) == 1)
    page.keyboard.press("F10")
    wait_for("Step Over to reach cycle 2", lambda: top_frame_cycle(bench) == 2)

    bench.step = "step-back"
    # The debug toolbar's Step Back button (shown when the adapter supports stepping back).
    page.locator(".codicon-debug-step-back").first.click()
    wait_for("Step Back to return to cycle 1", lambda: top_frame_cycle(bench) == 1)

    bench.step = "breakpoint"
    bench.open_file("fig3.gbas")
    bench.goto_line(3, 3)
    bench.command("Debug: Toggle Breakpoint")
    page.keyboard.press("F5")

    def stopped_on_line_3():
        cycle = top_frame_cycle(bench)
        frames = bench.call_stack_frames()
        return cycle is not None and cycle > 2 and any(re.search(r"fig3\.gbas\s*3:", f) for f in frames) and frames

    wait_for("the breakpoint on line 3 (m_depth past 15 m)", stopped_on_line_3, timeout=60)
    page.keyboard.press("Shift+F5")
    wait_for("the session to end", lambda: not bench.call_stack_frames(), timeout=20)
    check((workspace / "fig3.gbas").read_text() == original_fig3, "the test's typing reached fig3.gbas on disk")

    bench.step = "missing-binary"
    bench.clear_toasts()
    bench.set_user_setting("gloc.path", "no-such-dir/gloc")  # relative: the workspace folder

    def missing_toasts():
        return [t for t in bench.toasts() if "gloc" in t.lower() and ("not found" in t or "could not" in t)]

    wait_for("the missing binary's notification naming the workspace-relative path",
             lambda: any(str(workspace / "no-such-dir" / "gloc") in t for t in missing_toasts()), timeout=30)

    wait_for("a notification that the binary is missing", missing_toasts, timeout=30)
    time.sleep(3)  # a second notification for the same cause would arrive by now
    check(len(missing_toasts()) == 1, f"one missing binary gave {len(missing_toasts())} notifications: {bench.toasts()}")
    bench.clear_toasts()

    bench.step = "missing-binary-f5"
    bench.open_file("fig3.gbas")
    page.keyboard.press("F5")
    wait_for("F5 to say the binary is missing", missing_toasts, timeout=20)
    time.sleep(2)
    check(len(missing_toasts()) == 1, f"F5 with a missing binary gave {bench.toasts()}")
    button = page.locator(".notifications-toasts .notification-toast .monaco-button", has_text="Open Settings")
    check(button.count() == 1, "the missing-binary notification has no Open Settings button")
    button.first.click()
    wait_for(
        "the settings editor at gloc.path",
        lambda: page.locator(".settings-editor .setting-item-contents", has_text="Path").count() > 0,
        timeout=20,
    )
    bench.clear_toasts()

    bench.step = "bare-gloc-on-path"
    # `gloc` as installed by `cargo install`: in ~/.cargo/bin, which the login profile of this
    # test's home does not put on PATH.
    cargo_bin = home / ".cargo" / "bin"
    cargo_bin.mkdir(parents=True, exist_ok=True)
    (cargo_bin / "gloc").symlink_to(gloc_bin)
    bench.set_user_setting("gloc.path", "gloc")
    time.sleep(4)
    check(not missing_toasts(), f"a bare gloc in ~/.cargo/bin was not found: {bench.toasts()}")
    bench.open_file("fig3.gbas")
    bench.goto_line(2, 5)
    bench.command("Show or Focus Hover")
    wait_for("a hover from the server found in ~/.cargo/bin", hover_text, timeout=30)
    bench.step = "done"


if __name__ == "__main__":
    main()
