#!/bin/sh
# guest.sh - the part of make bench that runs inside the PREEMPT_RT guest
# (scripts/vm-test; this machine's kernel has no CAN): a cangen -g 0 flood
# and cyclictest, each without rtsup-trace, with it as shipped, with
# --no-overhead (no BPF statistics) and with the floor (empty programs on
# the same hooks), interleaved, REPS times. Then perf bench syscall basic
# (getppid, a syscall no per-syscall hook is on, by a thread that is no
# target) with the syscall hooks on raw_syscalls and per syscall, each
# with our programs and with the floor's: the host refuses fentry.
# One JSON object per measurement on stdout; rtsup-trace's own output goes
# to OUT (a directory under build/, which the guest shares with the host).
#
#   sh scripts/bench.d/guest.sh OUT REPS FRAMES LOOPS [CALLS]
set -u
OUT=$1 REPS=$2 FRAMES=$3 LOOPS=$4 CALLS=${5:-1000000}
T=build/rtsup-trace
TP=

now() { date +%s%N; }

# start_trace TAG ARGS... - rtsup-trace in the background, until it is attached
start_trace() {
	tag=$1
	shift
	$T -j "$@" > "$OUT/trace-$tag.json" 2> "$OUT/trace-$tag.err" &
	TP=$!
	i=0
	while ! grep -q "tracing with" "$OUT/trace-$tag.err" 2>/dev/null; do
		i=$((i + 1))
		if [ $i -gt 600 ] || ! kill -0 $TP 2>/dev/null; then
			echo "{\"error\": \"rtsup-trace did not start ($tag)\"}"
			return 1
		fi
		sleep 0.1
	done
}

stop_trace() {
	kill -INT $TP
	wait $TP
}

# variants in the order of round r: a different one goes first each round
# (rtsup-trace as shipped, without its BPF statistics: --no-overhead, and
# the floor: the same hooks with empty programs, --floor --no-overhead)
order() {
	case $(($1 % 4)) in
	1) echo "base rtsup nostats floor" ;;
	2) echo "rtsup nostats floor base" ;;
	3) echo "nostats floor base rtsup" ;;
	*) echo "floor base rtsup nostats" ;;
	esac
}

# trace_args VARIANT - rtsup-trace's options for a variant
trace_args() {
	case $1 in
	nostats) echo "--no-overhead" ;;
	floor) echo "--floor --no-overhead" ;;
	esac
}

ip link add dev vcan0 type vcan && ip link set up vcan0 || exit 1
echo "{\"part\": \"info\", \"kernel\": \"$(uname -r)\", \"uname_v\": \"$(uname -v)\", \"cpus\": $(nproc)}"
# warm-up: the binaries come over 9p and TCG translates their code once
cangen vcan0 -I 321 -L 8 -g 0 -n 5000
cyclictest -m -p 80 -t 2 -d 0 -i 1000 -l 200 -q > /dev/null

for r in $(seq "$REPS"); do
	for v in $(order "$r"); do
		tag=can-$v-$r
		if [ "$v" != base ]; then
			# shellcheck disable=SC2046
			start_trace "$tag" --can vcan0 -i 1s $(trace_args "$v") || continue
		fi
		a=$(now)
		cangen vcan0 -I 321 -L 8 -g 0 -n "$FRAMES"
		rc=$?
		b=$(now)
		[ "$v" != base ] && stop_trace
		echo "{\"part\": \"can\", \"variant\": \"$v\", \"rep\": $r, \"frames\": $FRAMES, \"ns\": $((b - a)), \"rc\": $rc, \"tag\": \"$tag\"}"
	done
done

for r in $(seq "$REPS"); do
	for v in $(order "$r"); do
		tag=cyc-$v-$r
		if [ "$v" != base ]; then
			# shellcheck disable=SC2046
			start_trace "$tag" --comm cyclictest -i 1s $(trace_args "$v") || continue
		fi
		cyclictest -m -p 80 -t 2 -d 0 -i 1000 -l "$LOOPS" -q > "$OUT/$tag.txt" 2>&1
		rc=$?
		[ "$v" != base ] && stop_trace
		echo "{\"part\": \"cyclictest\", \"variant\": \"$v\", \"rep\": $r, \"loops\": $LOOPS, \"rc\": $rc, \"tag\": \"$tag\"}"
	done
done

# the syscall hooks: variants in a rotating order, rtsup-trace --no-overhead
# on raw_syscalls and per syscall, and the floor of each
sys_order() {
	r=$1
	set -- base raw per rawfloor perfloor
	i=0
	while [ $i -lt $((r % 5)) ]; do
		set -- "$2" "$3" "$4" "$5" "$1"
		i=$((i + 1))
	done
	echo "$@"
}

sys_args() {
	case $1 in
	raw) echo "--no-overhead --syscall-hooks raw" ;;
	per) echo "--no-overhead --syscall-hooks per-syscall" ;;
	rawfloor) echo "--floor --no-overhead --syscall-hooks raw" ;;
	perfloor) echo "--floor --no-overhead --syscall-hooks per-syscall" ;;
	esac
}

perf bench syscall basic -l 10000 > /dev/null 2>&1
for r in $(seq "$REPS"); do
	for v in $(sys_order "$r"); do
		tag=sys-$v-$r
		if [ "$v" != base ]; then
			# a target that makes no syscall here (init): the workload is none
			# shellcheck disable=SC2046
			start_trace "$tag" -p 1 -i 1s $(sys_args "$v") || continue
		fi
		a=$(now)
		perf bench syscall basic -l "$CALLS" > /dev/null 2>&1
		rc=$?
		b=$(now)
		[ "$v" != base ] && stop_trace
		echo "{\"part\": \"syscall\", \"variant\": \"$v\", \"rep\": $r, \"calls\": $CALLS, \"ns\": $((b - a)), \"rc\": $rc, \"tag\": \"$tag\"}"
	done
done
