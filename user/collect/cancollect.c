// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/* cancollect.c - read the kernel's CAN maps into the CAN model */
#include <errno.h>
#include <net/if.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <bpf/bpf.h>
#include <bpf/libbpf.h>
#include <netlink/route/link.h>
#include <netlink/route/link/can.h>
#include "collect/cancollect.h"
#include "can.h"	/* the skeleton's .bss holds can_if_slot */
#include "rtsup.skel.h"

int can_resolve(struct options *o)
{
	int i;

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
	struct nl_sock *sk = nl_socket_alloc();
	struct rtnl_link *link = NULL;
	uint32_t state;

	if (!sk)
		return;
	if (!nl_connect(sk, NETLINK_ROUTE) &&
	    !rtnl_link_get_kernel(sk, f->ifindex, NULL, &link))
		can_iface_link(f, rtnl_link_get_flags(link) & IFF_UP,
			       rtnl_link_is_can(link) && !rtnl_link_can_state(link, &state) ?
			       (int)state : -1);
	rtnl_link_put(link);
	nl_socket_free(sk);
}

/* take_if - one interface's counters; its name and bitrate when first seen */
static void take_if(struct can_model *m, __u32 ifindex, const struct rtsup_can_if *v,
		    const struct options *o, const struct config *cfg)
{
	struct can_iface *f = can_iface_get(m, ifindex, true);

	if (!f)
		return;
	if (!f->cur.frames[0] && !f->cur.frames[1] && !f->have_prev) {
		char name[IF_NAMESIZE];

		if (if_indextoname(ifindex, name))
			snprintf(f->name, sizeof(f->name), "%s", name);
		f->bitrate = can_bitrate(ifindex);
	}
	if (o->can_bitrate)
		f->bitrate = o->can_bitrate;
	else if (!f->bitrate)
		f->bitrate = cfg->can.bitrate;
	f->cur = *v;
	can_link(f);
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
	__u32 key, next, *prev = NULL;
	struct rtsup_can_if v;

	for (key = 0; key < RTSUP_CAN_IF_SLOTS; key++) {
		/* the kernel writes while we copy: each counter is one aligned word */
		v = skel->bss->can_if_slot[key];
		if (can_if_seen(&v))
			take_if(m, key, &v, o, cfg);
	}
	while (!bpf_map_get_next_key(fd, prev, &next)) {
		key = next;
		prev = &key;
		if (!bpf_map_lookup_elem(fd, &key, &v))
			take_if(m, key, &v, o, cfg);
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
