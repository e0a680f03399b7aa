#!/usr/bin/env python3
"""Snakemake --cluster-status for Slurm without accounting: prints running | success | failed
for a job id, from `scontrol show job` (which keeps finished jobs for MinJobAge, 300 s by
default) and, when the job is gone from there, `squeue`."""
import subprocess
import sys

RUNNING = {"PENDING", "CONFIGURING", "RUNNING", "COMPLETING", "SUSPENDED", "REQUEUED", "RESIZING",
           "STAGE_OUT", "SIGNALING", "REQUEUE_HOLD", "REQUEUE_FED"}


def state(job_id):
    out = subprocess.run(["scontrol", "-o", "show", "job", job_id], stdout=subprocess.PIPE,
                         stderr=subprocess.DEVNULL, text=True)
    for field in out.stdout.split():
        if field.startswith("JobState="):
            return field.split("=", 1)[1]
    out = subprocess.run(["squeue", "-h", "-j", job_id, "-o", "%T"], stdout=subprocess.PIPE,
                         stderr=subprocess.DEVNULL, text=True)
    return out.stdout.strip() or None


job_state = state(sys.argv[1])
if job_state is None:
    # Forgotten by the controller: the job ended long ago; Snakemake checks its output files.
    print("failed")
    print(f"status.py: Slurm job {sys.argv[1]} is unknown to scontrol and squeue", file=sys.stderr)
elif job_state in RUNNING:
    print("running")
elif job_state == "COMPLETED":
    print("success")
else:
    print("failed")
