// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/* cancollect.c - read the kernel's CAN maps into the CAN model */
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <net/if.h>
#include <sched.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <bpf/bpf.h>
#include <bpf/libbpf.h>
#include <netlink/route/link.h>
#include <netlink/route/link/can.h>
#include "collect/cancollect.h"
#include "can.h"	/* the skeleton's .bss holds can_if_slot */
#include "rtsup.skel.h"

int can_resolve(struct options *o)
{
	struct stat st;
	int i;

	if (stat("/proc/self/ns/net", &st)) {
		fprintf(stderr, "rtsup-trace: /proc/self/ns/net: %s\n", strerror(errno));
		return -1;
	}
	o->can_netns = st.st_ino;
	for (i = 0; i < o->ncan; i++) {
		o->can_ifindex[i] = if_nametoindex(o->can_ifs[i]);
		if (!o->can_ifindex[i]) {
			fprintf(stderr, "rtsup-trace: --can %s: no such network interface\n",
				o->can_ifs[i]);
			return -1;
		}
	}
	return 0;
}

__u64 can_bitrate(__u32 ifindex)
{
	struct nl_sock *sk = nl_socket_alloc();
	struct rtnl_link *link = NULL;
	uint32_t rate = 0;

	if (!sk)
		return 0;
	/* a virtual CAN (vcan, vxcan) has no bit timing: 0, the config decides */
	if (!nl_connect(sk, NETLINK_ROUTE) && !rtnl_link_get_kernel(sk, ifindex, NULL, &link) &&
	    rtnl_link_is_can(link) && rtnl_link_can_get_bitrate(link, &rate))
		rate = 0;
	rtnl_link_put(link);
	nl_socket_free(sk);
	return rate;
}

/* can_link - netlink's word on an interface: up, and the controller's state (-1: none) */
static void can_link(struct can_iface *f)
{
	struct nl_sock *sk;
	struct rtnl_link *link = NULL;
	uint32_t state;

	if (!f->dev_ifindex) {	/* removed (an adapter unplugged): down until it is back */
		can_iface_link(f, false, -1);
		return;
	}
	sk = nl_socket_alloc();
	if (!sk)
		return;
	if (!nl_connect(sk, NETLINK_ROUTE) &&
	    !rtnl_link_get_kernel(sk, f->dev_ifindex, NULL, &link))
		can_iface_link(f, rtnl_link_get_flags(link) & IFF_UP,
			       rtnl_link_is_can(link) && !rtnl_link_can_state(link, &state) ?
			       (int)state : -1);
	rtnl_link_put(link);
	nl_socket_free(sk);
}

/*
 * foreign_name - "IFNAME@NS" for an interface of another network namespace
 * that `ip netns` named (/run/netns), else "ifN@net:INODE". The name is
 * read in a child that enters the namespace: this process never leaves its
 * own, where netlink and --can names mean what the user sees.
 */
static void foreign_name(__u32 netns, __u32 ifindex, char *buf, size_t len)
{
	char name[IF_NAMESIZE] = "", path[300];
	struct dirent *de;
	struct stat st;
	int p[2], fd, status;
	DIR *d = opendir("/run/netns");
	pid_t pid;

	snprintf(buf, len, "if%u@net:%u", ifindex, netns);
	while (d && (de = readdir(d))) {
		snprintf(path, sizeof(path), "/run/netns/%s", de->d_name);
		if (de->d_name[0] == '.' || stat(path, &st) || st.st_ino != netns)
			continue;
		fd = open(path, O_RDONLY | O_CLOEXEC);
		if (fd < 0 || pipe(p)) {
			if (fd >= 0)
				close(fd);
			break;
		}
		pid = fork();
		if (pid == 0) {
			close(p[0]);
			if (!setns(fd, CLONE_NEWNET) && if_indextoname(ifindex, name) &&
			    write(p[1], name, strlen(name)) < 0)
				_exit(1);
			_exit(0);
		}
		close(fd);
		close(p[1]);
		if (pid > 0 && read(p[0], name, sizeof(name) - 1) > 0)
			snprintf(buf, len, "%.15s@%.23s", name, de->d_name);
		close(p[0]);
		if (pid > 0)
			waitpid(pid, &status, 0);
		break;
	}
	if (d)
		closedir(d);
}

/* watched - which --can interface the kernel counts under 'key', -1: none */
static int watched(const struct rtsup_bpf *skel, const struct options *o, __u32 key)
{
	int i;

	for (i = 0; i < o->ncan; i++)
		if (skel->bss->can_watch[i].key == key)
			return i;
	return -1;
}

/* take_if - one interface's counters; its name and bitrate when first seen or back */
static void take_if(struct can_model *m, const struct rtsup_bpf *skel, __u32 netns,
		    __u32 ifindex, const struct rtsup_can_if *v, const struct options *o,
		    const struct config *cfg)
{
	struct can_iface *f = can_iface_get(m, netns, ifindex, true);
	bool own = netns == o->can_netns, first;
	int w = own ? watched(skel, o, ifindex) : -1;
	/* the ifindex it has now: a --can interface re-plugged has a new one, 0: gone */
	__u32 dev = w >= 0 ? skel->bss->can_watch[w].ifindex : own ? ifindex : 0;

	if (!f)
		return;
	first = !f->cur.frames[0] && !f->cur.frames[1] && !f->have_prev;
	if (first && w >= 0) {
		snprintf(f->name, sizeof(f->name), "%s", o->can_ifs[w]);
	} else if (first && own) {
		char name[IF_NAMESIZE];

		if (if_indextoname(dev, name))
			snprintf(f->name, sizeof(f->name), "%s", name);
	} else if (first) {
		foreign_name(netns, ifindex, f->name, sizeof(f->name));
	}
	/* an adapter plugged back may run another bitrate */
	if (own && dev && (first || dev != f->dev_ifindex))
		f->bitrate = can_bitrate(dev);
	if (o->can_bitrate)
		f->bitrate = o->can_bitrate;
	else if (!f->bitrate)
		f->bitrate = cfg->can.bitrate;
	f->dev_ifindex = dev;
	f->cur = *v;
	if (own)	/* netlink here speaks of our namespace's interfaces only */
		can_link(f);
}

/* can_follow - --can interfaces that were removed, or came back with a new ifindex */
static void can_follow(struct rtsup_bpf *skel, const struct options *o)
{
	int i;

	for (i = 0; i < o->ncan; i++) {
		__u32 now = if_nametoindex(o->can_ifs[i]);

		if (now != skel->bss->can_watch[i].ifindex)
			skel->bss->can_watch[i].ifindex = now;
	}
}

/* can_if_seen - has the kernel counted anything on this slot? */
static bool can_if_seen(const struct rtsup_can_if *v)
{
	return v->frames[0] || v->frames[1] || v->loopback || v->err_frames;
}

/* read_ifs - per-interface counters: the .bss slots, then the map */
static void read_ifs(struct can_model *m, struct rtsup_bpf *skel, const struct options *o,
		     const struct config *cfg)
{
	int fd = bpf_map__fd(skel->maps.can_ifs);
	struct rtsup_can_ifkey key, next, *prev = NULL;
	struct rtsup_can_if v;
	__u32 i;

	for (i = 0; i < RTSUP_CAN_IF_SLOTS; i++) {
		/* the kernel writes while we copy: each counter is one aligned word */
		v = skel->bss->can_if_slot[i];
		if (can_if_seen(&v))
			take_if(m, skel, o->can_netns, i, &v, o, cfg);
	}
	while (!bpf_map_get_next_key(fd, prev, &next)) {
		key = next;
		prev = &key;
		if (!bpf_map_lookup_elem(fd, &key, &v))
			take_if(m, skel, key.netns, key.ifindex, &v, o, cfg);
	}
}

void can_collect(struct can_model *m, struct rtsup_bpf *skel, const struct options *o,
		 const struct config *cfg)
{
	int fd = bpf_map__fd(skel->maps.can_ids);
	struct rtsup_can_key key, next, *prev = NULL;
	struct rtsup_can_id *v = malloc(sizeof(*v));
	struct can_entry *e;

	if (!v)
		return;
	can_follow(skel, o);
	/* the map is written by the kernel only and never reset from here, so
	 * every frame is counted once whatever the interval */
	read_ifs(m, skel, o, cfg);
	while (!bpf_map_get_next_key(fd, prev, &next)) {
		key = next;
		prev = &key;
		if (bpf_map_lookup_elem(fd, &key, v))
			continue;
		e = can_entry_get(m, &key, true);
		if (e)
			e->cur = *v;
	}
	free(v);
}
