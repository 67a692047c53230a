#!/usr/bin/env python3
"""Trims an `apitrace dump --multiline=false` listing to what `clipray check --trace` reads.

    trim-dump.py FRAMES HEADER < full.dump.txt > trimmed.dump.txt

Keeps the calls of the first FRAMES frames (through the FRAMES-th glXSwapBuffers/eglSwapBuffers;
0: all) and drops only the bulk that never changes a reading: per-vertex immediate-mode
attributes (glVertex*, glNormal*, glColor*, glTexCoord*, ...) and state queries (glGet*, except
glGetUniformLocation*, glGetUniformBlockIndex, glGetActiveUniform* and glGetProgramResource*,
whose results name uniforms and blocks).
Every other call is kept whether clipray follows it today or not, with its own call number, so
the readings of the trimmed listing are those of the whole trace over the same frames.
HEADER is written first as "//" lines (the program, its version, the command).
"""
import re
import sys

DROPPED = re.compile(
    r"^(glVertex[234]|glNormal3|glColor[34]|glSecondaryColor|glTexCoord[1234]|glMultiTexCoord"
    r"|glEdgeFlag|glFogCoord|glIndex[dfis]|glArrayElement|glEvalCoord|glEvalPoint"
    r"|glGet(?!UniformLocation|UniformBlockIndex|ActiveUniform|ProgramResource))")
CALL = re.compile(r"^(\d+) (\w+)\(")
SWAP = re.compile(r"SwapBuffers|glFrameTerminatorGREMEDY")


def main():
    frames = int(sys.argv[1])
    for line in sys.argv[2].splitlines():
        print("// " + line)
    ended = 0
    for line in sys.stdin:
        line = line.rstrip("\n")
        call = CALL.match(line)
        if not call:
            continue  # apitrace's own comment lines; the header says where the dump came from
        if DROPPED.match(call.group(2)):
            continue
        print(line)
        if SWAP.search(call.group(2)):
            ended += 1
            if frames and ended == frames:
                break
    for _ in sys.stdin:
        pass  # read to the end: apitrace dump, cut off, would fail the pipe (set -o pipefail)


main()
