#!/usr/bin/python3
"""Capture one presented frame of an unmodified program with RenderDoc: `renderdoccmd capture`
launches it (RenderDoc injected), then this script connects to it through RenderDoc's target
control (python3-renderdoc), triggers a capture of the next frame once the program presents, waits
for the .rdc and ends the program.

  clipray-capture-frame.py OUT.rdc [--timeout S] -- PROGRAM [ARGS...]

`renderdoccmd capture` alone has no frame trigger (F12/PrtScr in the program's window, or target
control): this is the target control. The program must present (glXSwapBuffers / eglSwapBuffers)
and make a context RenderDoc captures: core-profile GL 3.2+ or GLES through EGL. A legacy or
compatibility GL program (glxgears, glmark2-x11) is refused by RenderDoc: it registers the API as
not supported ("Unsupported functions used: glBegin ...") and this script fails with that message.
Run it under a display (xvfb-run). Exit status 0 with OUT.rdc written, 1 with one line on stderr.
"""

import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time


def fail(message):
    sys.stderr.write("clipray-capture-frame: " + message + "\n")
    sys.exit(1)


def main():
    args = sys.argv[1:]
    if "--" not in args or args.index("--") < 1 or args.index("--") == len(args) - 1:
        fail("usage: clipray-capture-frame.py OUT.rdc [--timeout S] -- PROGRAM [ARGS...]")
    split = args.index("--")
    options, program = args[:split], args[split + 1:]
    out, timeout = options[0], 30.0
    if len(options) == 3 and options[1] == "--timeout":
        timeout = float(options[2])
    elif len(options) != 1:
        fail("unknown options " + " ".join(options[1:]))
    try:
        import renderdoc as rd
    except ImportError as error:
        fail("RenderDoc's Python module is missing (" + str(error) +
             "): install Debian's python3-renderdoc")
    if shutil.which("renderdoccmd") is None:
        fail("renderdoccmd is missing: install Debian's renderdoccmd")
    folder = tempfile.mkdtemp(prefix="clipray-capture-")
    # renderdoccmd's output to a file, not a pipe: the program inherits it and keeps running.
    log = os.path.join(folder, "renderdoccmd.log")
    with open(log, "w") as output:
        subprocess.call(["renderdoccmd", "capture", "-c", os.path.join(folder, "frame")] +
                                 program, stdout=output, stderr=subprocess.STDOUT)
    with open(log) as output:
        said = output.read()
    ident = re.search(r"Launched as ID (\d+)", said)
    if ident is None:  # its exit status is not 0 when it launched
        fail("renderdoccmd capture did not launch " + program[0] + ": " +
             said.strip().replace("\n", " / "))
    control = rd.CreateTargetControl("", int(ident.group(1)), "clipray", True)
    if control is None:
        fail("no target control connection to " + program[0] + " (RenderDoc ID " +
             ident.group(1) + ")")
    pid = control.GetPID()
    path = None
    try:
        deadline = time.time() + timeout
        triggered = False
        while time.time() < deadline and path is None:
            message = control.ReceiveMessage(None)
            kind = message.type
            if kind == rd.TargetControlMessageType.Disconnected:
                fail(program[0] + " ended before a frame was captured")
            if kind == rd.TargetControlMessageType.RegisterAPI:
                use = message.apiUse
                if use.presenting and not use.supported:
                    why = use.supportMessage.strip().replace("\n", " ") or (
                        "not supported (RenderDoc captures core-profile GL 3.2+ and GLES only; "
                        "its log under /tmp/RenderDoc names the context)")
                    fail("RenderDoc does not capture " + program[0] + "'s " + use.name +
                         " context: " + why)
                if use.presenting and use.supported and not triggered:
                    control.TriggerCapture(1)  # the next frame it presents
                    triggered = True
            if kind == rd.TargetControlMessageType.NewCapture:
                path = message.newCapture.path
        if path is None:
            fail("no capture of " + program[0] + " within " + str(timeout) + " s")
    finally:
        control.Shutdown()
        if pid:
            try:
                os.kill(pid, signal.SIGTERM)
            except ProcessLookupError:
                pass
    shutil.move(path, out)
    shutil.rmtree(folder, ignore_errors=True)


if __name__ == "__main__":
    main()
