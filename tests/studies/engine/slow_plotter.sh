#!/bin/sh
# Stands in for python3 (VRV_PYTHON) in the interruption test: records its pid, then plots nothing
# for a minute, so that the test can interrupt vrv while its child runs.
echo $$ > "$VRV_TEST_PLOTTER_PID.tmp" && mv "$VRV_TEST_PLOTTER_PID.tmp" "$VRV_TEST_PLOTTER_PID"
sleep 60
