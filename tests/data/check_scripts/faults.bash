#!/usr/bin/env bash
set -euo pipefail
# a comment may say ls | head
first=$(ls / | head -n 1)
ls / | grep -q usr && echo yes
ls / | grep -m 1 usr
ls / | sed 1q
ls / || head -n 1 /etc/hostname
ls / | awk 'NR == 1'
ls / | head -c 10 || true
