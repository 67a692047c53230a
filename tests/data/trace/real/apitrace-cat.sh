#!/bin/sh
# Stands in for apitrace (CLIPRAY_APITRACE) where the trace is already an `apitrace dump
# --multiline=false` listing, as the recorded dumps here are: `apitrace-cat.sh dump [OPTIONS] --
# FILE` prints FILE. Used by tests/trace/RealProgramsTest.cpp; `clipray check --trace` streams
# the listing as it streams apitrace's.
for last; do :; done
exec cat -- "$last"
