#!/usr/bin/env python3
"""Trims an `apitrace dump --multiline=false` listing to what `clipray check --trace` reads.

    trim-dump.py FRAMES HEADER [lean] < full.dump.txt > trimmed.dump.txt

Keeps the calls of the first FRAMES frames (through the FRAMES-th glXSwapBuffers/eglSwapBuffers;
0: all) and drops only the bulk that never changes a reading: per-vertex immediate-mode
attributes (glVertex*, glNormal*, glColor*, glTexCoord*, ...), state queries (glGet*, except
glGetUniformLocation*, glGetUniformBlockIndex, glGetActiveUniform* and glGetProgramResource*,
whose results name uniforms and blocks) and GLX framebuffer-configuration queries
(glXChooseFBConfig, glXGetVisualFromFBConfig, glXGetFBConfig*: a Qt program lists every
configuration of the screen, 200 KB and more).
Every other call is kept whether clipray follows it today or not, with its own call number, so
the readings of the trimmed listing are those of the whole trace over the same frames.
HEADER is written first as "//" lines (the program, its version, the command).
With "lean" (for a program whose first frame alone is large: Stellarium's start-up uploads
hundreds of textures), it drops as well the calls that set state clipray does not follow and
that holds no matrix: texture parameters and sub-images, pixel storage, vertex attribute arrays
and constant attributes, blending, non-matrix uniforms, attribute bindings, mipmap generation.
"""
import re
import sys

DROPPED = re.compile(
    r"^(glVertex[234]|glNormal3|glColor[34]|glSecondaryColor|glTexCoord[1234]|glMultiTexCoord"
    r"|glEdgeFlag|glFogCoord|glIndex[dfis]|glArrayElement|glEvalCoord|glEvalPoint"
    r"|glGet(?!UniformLocation|UniformBlockIndex|ActiveUniform|ProgramResource)"
    r"|glXChooseFBConfig|glXGetVisualFromFBConfig|glXGetFBConfig)")
LEAN = re.compile(
    r"^(glTexParameter|glTexSubImage|glPixelStore|glVertexAttrib[1-4]|glVertexAttribPointer"
    r"|glEnableVertexAttribArray|glDisableVertexAttribArray|glBlendFunc|glBlendEquation"
    r"|glUniform[1-4]|glBindAttribLocation|glGenerateMipmap)")
CALL = re.compile(r"^(\d+) (\w+)\(")
SWAP = re.compile(r"SwapBuffers|glFrameTerminatorGREMEDY")


def main():
    frames = int(sys.argv[1])
    lean = len(sys.argv) > 3 and sys.argv[3] == "lean"
    for line in sys.argv[2].splitlines():
        print("// " + line)
    ended = 0
    for line in sys.stdin:
        line = line.rstrip("\n")
        call = CALL.match(line)
        if not call:
            continue  # apitrace's own comment lines; the header says where the dump came from
        if DROPPED.match(call.group(2)) or (lean and LEAN.match(call.group(2))):
            continue
        print(line)
        if SWAP.search(call.group(2)):
            ended += 1
            if frames and ended == frames:
                break
    for _ in sys.stdin:
        pass  # read to the end: apitrace dump, cut off, would fail the pipe (set -o pipefail)


main()
