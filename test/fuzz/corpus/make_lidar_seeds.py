#!/usr/bin/env python3
"""Writes the LiDAR fuzz seed corpora (test/fuzz/corpus/lidar_*/).

Stream seeds follow test/sensing/fuzz_lidar_common.h: two flag bytes, then
packets as [uint16 little-endian length][payload]. Run from anywhere:
  python3 test/fuzz/corpus/make_lidar_seeds.py [path/to/vlp16_sample.pcap]
The capture defaults to the repository's test/data/vlp16_sample.pcap.
"""
import math
import os
import struct
import sys

HERE = os.path.dirname(os.path.abspath(__file__))


def stream(flags, packets):
    out = bytes(flags)
    for p in packets:
        out += struct.pack('<H', len(p)) + p
    return out


def vlp16_packet(az0, gap, t_us, mode=0x37, rng=10.0):
    elev = [-15, 1, -13, 3, -11, 5, -9, 7, -7, 9, -5, 11, -3, 13, -1, 15]
    out = b''
    for b in range(12):
        col = b // 2 if mode == 0x39 else b
        az = int(round((az0 + gap * col) * 100)) % 36000
        out += b'\xff\xee' + struct.pack('<H', az)
        for s in range(2):
            for l in range(16):
                d = rng / math.cos(math.radians(elev[l])) + (1.0 if mode == 0x39 and b % 2 else 0.0)
                out += struct.pack('<HB', int(round(d / 0.002)), 10 + l)
    return out + struct.pack('<I', t_us % 3600000000) + bytes([mode, 0x22])


def helios_msop(az0, gap, utc_us, rng=8.0):
    out = bytes([0x55, 0xAA, 0x05, 0x5A]) + bytes(16)
    out += (utc_us // 1000000).to_bytes(6, 'big') + (utc_us % 1000000).to_bytes(4, 'big')
    out += bytes(12)
    for b in range(12):
        az = int(round((az0 + gap * b) * 100)) % 36000
        out += b'\xff\xee' + struct.pack('>H', az)
        for c in range(32):
            out += struct.pack('>HB', int(round(rng / 0.0025)), c)
    out += struct.pack('>I', 7) + b'\x00\xff'
    assert len(out) == 1248
    return out


def helios_difop(mode=0x04):
    out = bytearray(1248)
    out[0:8] = bytes([0xA5, 0xFF, 0x00, 0x5A, 0x11, 0x11, 0x55, 0x55])
    out[8:10] = struct.pack('>H', 600)
    out[300] = mode
    for c in range(32):
        v = -25.0 + 1.25 * c
        out[468 + 3 * c:471 + 3 * c] = bytes([1 if v < 0 else 0]) + struct.pack('>H', int(round(abs(v) * 100)))
        h = 0.02 * (c % 3) - 0.02
        out[564 + 3 * c:567 + 3 * c] = bytes([1 if h < 0 else 0]) + struct.pack('>H', int(round(abs(h) * 100)))
    return bytes(out)


def sample_payloads(path):
    d = open(path, 'rb').read()
    off, out = 24, []
    while off + 16 <= len(d):
        _, _, incl, _ = struct.unpack('<IIII', d[off:off + 16])
        pkt = d[off + 16:off + 16 + incl]
        off += 16 + incl
        ihl = (pkt[14] & 15) * 4
        out.append(pkt[14 + ihl + 8:])
    return out


def pcap(link_type, frames, snaplen=65535):
    out = struct.pack('<IHHiIII', 0xa1b2c3d4, 2, 4, 0, 0, snaplen, link_type)
    for i, (frame, orig_len) in enumerate(frames):
        out += struct.pack('<IIII', 1700000000, 1327 * i, len(frame), max(orig_len, len(frame))) + frame
    return out


def udp_ipv4(payload, dport=2368, frag=0):
    udp = struct.pack('>HHHH', 2368, dport, 8 + len(payload), 0) + payload
    ip = struct.pack('>BBHHHBBH4s4s', 0x45, 0, 20 + len(udp), 1, frag, 64, 17, 0,
                     bytes([192, 168, 1, 201]), bytes([255, 255, 255, 255]))
    return ip + udp


def udp_ipv6(payload, dport=2368):
    udp = struct.pack('>HHHH', 2368, dport, 8 + len(payload), 0) + payload
    return struct.pack('>IHBB16s16s', 0x60000000, len(udp), 17, 64, bytes(16), bytes(15) + b'\x01') + udp


def ether(ip, ethertype=0x0800, vlan=False):
    head = bytes(6) + bytes([0x60, 0x76, 0x88, 0, 0, 1])
    if vlan:
        head += struct.pack('>HH', 0x8100, 5)
    return head + struct.pack('>H', ethertype) + ip


def write(dirname, name, data):
    os.makedirs(os.path.join(HERE, dirname), exist_ok=True)
    with open(os.path.join(HERE, dirname, name), 'wb') as f:
        f.write(data)


def main():
    gap = 0.398  # deg per block at 10 Hz
    t0 = 1234567
    write('lidar_vlp16', 'synthetic_wrap', stream([0, 0], [vlp16_packet(355.0 + 4.78 * k, gap, t0 + 1327 * k) for k in range(3)]))
    write('lidar_vlp16', 'synthetic_dual', stream([0, 1], [vlp16_packet(358.0 + 2.39 * k, gap, t0 + 664 * k, 0x39) for k in range(3)]))
    write('lidar_vlp16', 'single_packet', vlp16_packet(10.0, gap, t0))
    sample = sys.argv[1] if len(sys.argv) > 1 else os.path.join(HERE, '../../data/vlp16_sample.pcap')
    p = sample_payloads(sample)
    # real packets around the azimuth wrap, with a position packet
    write('lidar_vlp16', 'sample_wrap', stream([0, 0], [p[i] for i in range(26, 31)] + [p[3]]))
    # the head of the real capture: data and position packets, Ethernet
    d = open(sample, 'rb').read()
    off = 24
    for _ in range(6):
        incl = struct.unpack('<IIII', d[off:off + 16])[2]
        off += 16 + incl
    write('lidar_pcap', 'sample_head.pcap', d[:off])
    pk = [vlp16_packet(359.0 + 4.78 * k, gap, t0 + 1327 * k) for k in range(3)]
    write('lidar_pcap', 'vlan_fragment_truncated.pcap', pcap(1, [
        (ether(udp_ipv4(pk[0]), vlan=True), 0),
        (ether(udp_ipv4(pk[1], frag=0x2000)), 0),
        (ether(udp_ipv4(pk[2]))[:600], 0),
        (ether(udp_ipv4(b'\x00' * 512, dport=8308)), 0)]))
    cooked = struct.pack('>HHH8sH', 0, 1, 6, bytes(8), 0x86DD)
    write('lidar_pcap', 'linux_cooked_ipv6.pcap', pcap(113, [(cooked + udp_ipv6(p), 0) for p in pk]))
    write('lidar_pcap', 'raw_ip.pcap', pcap(101, [(udp_ipv4(p), 0) for p in pk]))
    hgap = 0.2
    u0 = 1700000000000000
    write('lidar_rs_helios', 'difop_then_msop',
          stream([0, 0], [helios_difop()] + [helios_msop(357.0 + 2.4 * k, hgap, u0 + 667 * k) for k in range(3)]))
    write('lidar_rs_helios', 'msop_before_difop_dual',
          stream([1, 1], [helios_msop(10.0, hgap, u0), helios_difop(0x00), helios_msop(12.4, hgap, u0 + 667)]))
    write('lidar_rs_helios', 'single_msop', helios_msop(100.0, hgap, u0))
    write('lidar_rs_helios', 'single_difop', helios_difop())


if __name__ == '__main__':
    main()
