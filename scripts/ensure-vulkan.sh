#!/usr/bin/env bash
# Installs Mesa's Vulkan drivers (lavapipe, a software Vulkan device) when no Vulkan driver is
# present, so the GPU path runs on machines without a GPU. Needs root or sudo for apt-get.
set -euo pipefail
if compgen -G "/usr/share/vulkan/icd.d/*.json" >/dev/null || compgen -G "/etc/vulkan/icd.d/*.json" >/dev/null; then
  exit 0
fi
sudo=""
if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
echo "installing mesa-vulkan-drivers (software Vulkan) ..." >&2
$sudo apt-get update -qq
DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq mesa-vulkan-drivers >/dev/null
