#!/usr/bin/env bash
# DDS Security material for one mission: a mission CA and one identity per participant, for
# Fast DDS's builtin PKI-DH authentication (ECDSA P-256) and AES-GCM encryption (dds/participant.cpp).
#
#   deploy/security/make_certs.sh OUT_DIR NAME...      e.g.  out/security base sim robot0 robot1
#
# Writes OUT_DIR/ca.pem and OUT_DIR/ca.key (the CA's key: keep it off the robots), and for each NAME
# the folder OUT_DIR/NAME with ca.pem, cert.pem and key.pem: what `--security OUT_DIR/NAME` of
# cairn_agent, cairn_base and cairn_sim reads. An existing CA is reused, so identities can be added
# to a running mission's team later. Certificates are valid for 30 days.
set -euo pipefail
if [ $# -lt 2 ]; then
  echo "usage: $0 OUT_DIR NAME..." >&2
  exit 2
fi
command -v openssl > /dev/null || { echo "make_certs: openssl not found (apt-get install openssl)" >&2; exit 2; }
out=$1
shift
mkdir -p "$out"
umask 077
if [ ! -f "$out/ca.key" ]; then
  openssl ecparam -name prime256v1 -genkey -noout | openssl pkcs8 -topk8 -nocrypt -out "$out/ca.key"
  openssl req -new -x509 -key "$out/ca.key" -out "$out/ca.pem" -days 30 -sha256 \
    -subj "/O=Cairn/CN=Cairn mission CA" 2> /dev/null
fi
for name in "$@"; do
  case $name in
    */* | "" | .*) echo "make_certs: bad participant name '$name'" >&2; exit 2 ;;
  esac
  d=$out/$name
  mkdir -p "$d"
  openssl ecparam -name prime256v1 -genkey -noout | openssl pkcs8 -topk8 -nocrypt -out "$d/key.pem"
  openssl req -new -key "$d/key.pem" -out "$d/request.csr" -subj "/O=Cairn/CN=$name" 2> /dev/null
  openssl x509 -req -in "$d/request.csr" -CA "$out/ca.pem" -CAkey "$out/ca.key" -CAcreateserial \
    -out "$d/cert.pem" -days 30 -sha256 2> /dev/null
  cp "$out/ca.pem" "$d/ca.pem"
  rm -f "$d/request.csr"
done
