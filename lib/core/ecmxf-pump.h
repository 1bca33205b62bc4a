/* SPDX-License-Identifier: GPL-2.0-only OR MIT */
/*
 * ecmxf-pump.h - the PDO pump's policy over the chip's FIFOs (sans-I/O)
 *
 * What an ECAT_PDO_DATA_FIFO_OP should carry and what its answer means,
 * written once for the kernel's pump (kmod/ecmxf-pump.c, frames from the
 * mmap()ed rings) and for the library's FIFO-command path (frames from
 * the process image): how many RxPDO frames the RxFIFO has room for, the
 * command's header fields, and from the answer the frames popped, the
 * frames refused and the FIFO losses.  No I/O, no allocation, no clock:
 * the caller moves the frames and runs the commands.
 *
 * Copyright (C) 2026 The ecmxf authors
 */
#ifndef ECMXF_PUMP_H
#define ECMXF_PUMP_H

#include "ecmxf-proto.h"

#ifdef __cplusplus
extern "C" {
#endif

/*
 * frames kept free in the RxFIFO: the header's FIFO counts lag by up to
 * two exchanges (spec, "PDO exchange details")
 */
#define ECMXF_PUMP_RX_MARGIN	2U
/* RxPDO frames one command can carry: the command parameter is a byte */
#define ECMXF_PUMP_MAX_PUSH	255U

/* data byte 0 of ECAT_PDO_DATA_FIFO_OP */
#define ECMXF_PUMP_OP_WRITE	0x01U	/* push the frames into the RxFIFO */
#define ECMXF_PUMP_OP_READ	0x02U	/* pop TxPDO frames */
/* return value bit 0: the RxFIFO took the frames (clear: full, refused) */
#define ECMXF_PUMP_RET_TAKEN	0x01U

/* ecmxf_pump_next() flags */
#define ECMXF_PUMP_F_READ	0x01U	/* pop TxPDO frames (if there are any) */
#define ECMXF_PUMP_F_ONE	0x02U	/* offer one frame even to a full FIFO */

/**
 * struct ecmxf_pump - what the pump knows about the chip's FIFOs
 * @out_size: RxPDO frame bytes (FIFO_PACK_SIZE_GET 0), 0 without outputs
 * @in_size: TxPDO frame bytes (FIFO_PACK_SIZE_GET 1), 0 without inputs
 * @data_size: the data section size in force
 * @rx_fill: RxFIFO level the pump fills up to
 * @tx_depth: TxFIFO depth (FIFO_GET_TX_CNT), 0 unknown
 * @unconfirmed: frames of the previous command that the header's RxFIFO
 *	count may not show yet
 * @pushed_any: a frame has been pushed (an empty RxFIFO is an underrun
 *	only after that)
 *
 * Set up with ecmxf_pump_init(); ecmxf_pump_answer() keeps the last two.
 */
struct ecmxf_pump {
	u32 out_size;
	u32 in_size;
	u32 data_size;
	u32 rx_fill;
	u32 tx_depth;
	u32 unconfirmed;
	bool pushed_any;
};

/**
 * struct ecmxf_pump_plan - one planned ECAT_PDO_DATA_FIFO_OP
 * @skip: the oldest ready output frames to drop before pushing (the
 *	caller fell behind); counted by the caller, never sent
 * @push: output frames the command carries (after the skipped ones)
 * @read: the command pops TxPDO frames
 */
struct ecmxf_pump_plan {
	u32 skip;
	u32 push;
	bool read;
};

/**
 * struct ecmxf_pump_result - what an answer to the FIFO command says
 * @taken: output frames gone for good (the caller frees them): the pushed
 *	ones, unless the chip refused the whole command (command error)
 * @refused: of @taken, frames the full RxFIFO refused (RxFIFO overrun)
 * @popped: TxPDO frames in the answer's data
 * @tx_overrun: the TxFIFO was full: the chip dropped its oldest frames
 * @rx_underrun: the RxFIFO ran empty while the FIFOs were enabled
 */
struct ecmxf_pump_result {
	u32 taken;
	u32 refused;
	u32 popped;
	bool tx_overrun;
	bool rx_underrun;
};

/*
 * The schedule (ecmxf-pump-sched.c): which of the pump's commands goes
 * next, which answer belongs to which command, the frames counted in
 * flight, the RxFIFO estimate and what is skipped, lost and counted.
 */

/* the pump's commands: two FIFO commands (0, 1) and the WKC read */
#define ECMXF_PUMP_SLOTS	3U
#define ECMXF_PUMP_SLOT_WKC	2U

/* ecmxf_pump_sched_pick(): what goes next */
#define ECMXF_PUMP_PICK_NONE	0
#define ECMXF_PUMP_PICK_FIFO	1
#define ECMXF_PUMP_PICK_WKC	2

/* &ecmxf_pump_sched.flags */
#define ECMXF_PUMP_S_FIFO_NEXT	0x01U	/* a FIFO answer waits for the next */
#define ECMXF_PUMP_S_WKC_NEXT	0x02U	/* the WKC answer waits, likewise */

/* ecmxf_pump_sched_finish(): what a finished command's status means */
#define ECMXF_PUMP_DONE_ANSWER	0	/* answered: read the answer */
#define ECMXF_PUMP_DONE_FAILED	1	/* failed: ecmxf_pump_sched_failed() */
#define ECMXF_PUMP_DONE_STOP	2	/* the chip reset: the pump stops */

/**
 * struct ecmxf_pump_sched - the pump's timers (one set of rings, or one
 *	cyclic exchange)
 * @flags: %ECMXF_PUMP_S_FIFO_NEXT, %ECMXF_PUMP_S_WKC_NEXT
 * @poll_ns: the FIFO command period (the kernel's pump timer)
 * @wkc_ns: the working counter read period, 0 never
 * @next_tick_ns: the next timer-driven FIFO command
 * @next_wkc_ns: the next working counter read
 * @again: the last answer left work (frames queued either way): the next
 *	FIFO command is due at once
 * @kicked: the last FIFO command was brought forward by INT1 (before its
 *	timer, with no work left): INT1 brings no other one forward until a
 *	timer-driven or work-driven one went (ecmxf_pump_sched_kick_held())
 */
struct ecmxf_pump_sched {
	unsigned int flags;
	u64 poll_ns;
	u64 wkc_ns;
	u64 next_tick_ns;
	u64 next_wkc_ns;
	bool again;
	bool kicked;
};

/**
 * struct ecmxf_pump_flight - the pump's commands in flight
 * @plan: the FIFO commands' plans (slots 0 and 1)
 * @busy: the command of each slot is in flight (sent or about to be)
 * @released: a FIFO command's output frames were freed when it was sent
 *	(%ECMXF_PUMP_S_FIFO_NEXT), not when its answer came
 * @skipped: output frames skipped when a FIFO command was planned, not
 *	counted yet
 * @answer_by_ns: how long an answer may wait for the next FIFO command
 * @newest: the FIFO slot planned last (the other one, when busy, is the
 *	older: answers are taken oldest first)
 */
struct ecmxf_pump_flight {
	struct ecmxf_pump_plan plan[2];
	bool busy[ECMXF_PUMP_SLOTS];
	bool released[2];
	u32 skipped[2];
	u64 answer_by_ns[ECMXF_PUMP_SLOTS];
	unsigned int newest;
};

/**
 * struct ecmxf_pump_acct - what a finished FIFO command moves and counts
 * @free: output frames that leave the ring now (oldest first)
 * @dropped: output frames that never reached the bus (refused, lost, or
 *	dropped after a command error), counted as the ring's dropped
 * @store: TxPDO frames of the answer to store
 * @skipped: output frames skipped when the command was planned
 * @ops: FIFO commands answered (0 or 1)
 * @refusals: RxFIFO overruns (0 or 1)
 * @tx_overruns: TxFIFO overruns (0 or 1)
 * @rx_underruns: RxFIFO underruns (0 or 1)
 * @out_underruns: of those, with the output ring empty (0 or 1)
 * @failures: commands that failed with no answer (0 or 1)
 * @wake_out: the output ring has room again
 * @moved: the command moved frames (it took some, or popped some)
 * @answered: the answer was read whole (no command error, no -EPROTO)
 */
struct ecmxf_pump_acct {
	u32 free;
	u32 dropped;
	u32 store;
	u32 skipped;
	u32 ops;
	u32 refusals;
	u32 tx_overruns;
	u32 rx_underruns;
	u32 out_underruns;
	u32 failures;
	bool wake_out;
	bool moved;
	bool answered;
};

/**
 * struct ecmxf_pump_est - the RxFIFO and TxFIFO estimate of a host that
 *	keeps time (the library's FIFO path)
 * @bus_ns: the bus cycle, 0 unknown (one frame per cycle then)
 * @cycles: cycles since ecmxf_pump_est_start()
 * @rx_level: RxFIFO count in the answer to the last write
 * @rx_ns: when the chip ran that write
 * @rx_cycle: in which cycle
 * @tx_level: TxFIFO count in the answer to the last read
 * @tx_ns: when the chip ran that read
 */
struct ecmxf_pump_est {
	u64 bus_ns;
	u64 cycles;
	u32 rx_level;
	u64 rx_ns;
	u64 rx_cycle;
	u32 tx_level;
	u64 tx_ns;
};

/* ecmxf_pump_cycle: where a cycle of the library's FIFO path is */
#define ECMXF_PUMP_C_FIRST	0	/* the first command: push, read */
#define ECMXF_PUMP_C_READ	1	/* read-only commands for a backlog */
#define ECMXF_PUMP_C_WRITE	2	/* more writes up to the fill level */
#define ECMXF_PUMP_C_DONE	3

/**
 * struct ecmxf_pump_cycle - one cycle of synchronous FIFO commands
 * @level: the RxFIFO level estimated at the cycle's start
 * @pushed: frames pushed in the cycle
 * @reads: read-only commands sent
 * @state: %ECMXF_PUMP_C_FIRST ... %ECMXF_PUMP_C_DONE
 * @wkc: a working counter read is wanted
 * @wkc_carried: it rode with the first FIFO command
 * @refused: the RxFIFO refused frames: no more writes
 */
struct ecmxf_pump_cycle {
	u32 level;
	u32 pushed;
	u32 reads;
	unsigned int state;
	bool wkc;
	bool wkc_carried;
	bool refused;
};

u32 ecmxf_pump_max_fill(u32 rx_depth);
int ecmxf_pump_check(u32 out_size, u32 in_size, u32 data_size,
		     u32 rx_depth, u32 rx_fill);
void ecmxf_pump_init(struct ecmxf_pump *p, u32 out_size, u32 in_size,
		     u32 data_size, u32 rx_depth, u32 rx_fill, u32 tx_depth);
u32 ecmxf_pump_per_write(const struct ecmxf_pump *p);
u32 ecmxf_pump_per_read(const struct ecmxf_pump *p);
u32 ecmxf_pump_level(const struct ecmxf_pump *p,
		     const struct ecmxf_rsp_hdr *h);
bool ecmxf_pump_next(const struct ecmxf_pump *p, u32 level, u32 avail,
		     unsigned int flags, struct ecmxf_pump_plan *pl);
u32 ecmxf_pump_fifo_cmd(const struct ecmxf_pump *p,
			const struct ecmxf_pump_plan *pl, bool rearm,
			struct ecmxf_cmd_hdr *hdr);
int ecmxf_pump_answer(struct ecmxf_pump *p, const struct ecmxf_pump_plan *pl,
		      const struct ecmxf_rsp_hdr *h, u32 rx_len,
		      struct ecmxf_pump_result *res);
u32 ecmxf_pump_lost(struct ecmxf_pump *p, const struct ecmxf_pump_plan *pl);
void ecmxf_pump_wkc_cmd(struct ecmxf_cmd_hdr *hdr);
int ecmxf_pump_wkc_answer(const struct ecmxf_rsp_hdr *h, const u8 *data,
			  u32 len, u32 *wkc);

u32 ecmxf_pump_max_reads(const struct ecmxf_pump *p);
void ecmxf_pump_sched_init(struct ecmxf_pump_sched *s, unsigned int flags,
			   u64 poll_ns, u64 wkc_ns);
int ecmxf_pump_sched_pick(const struct ecmxf_pump_sched *s,
			  const struct ecmxf_pump_flight *f,
			  const struct ecmxf_rsp_hdr *h, u64 now, bool kick,
			  bool newest_sent);
bool ecmxf_pump_sched_kick_held(const struct ecmxf_pump_sched *s, u64 now);
u64 ecmxf_pump_sched_deadline(const struct ecmxf_pump_sched *s,
			      const struct ecmxf_rsp_hdr *h);
unsigned int ecmxf_pump_sched_fifo(struct ecmxf_pump_sched *s,
				   struct ecmxf_pump_flight *f, u64 now);
void ecmxf_pump_sched_wkc(struct ecmxf_pump_sched *s, u64 now);
u32 ecmxf_pump_flight_pushed(const struct ecmxf_pump_flight *f);
bool ecmxf_pump_flight_busy(const struct ecmxf_pump_flight *f);
u32 ecmxf_pump_sched_level(const struct ecmxf_pump *p,
			   const struct ecmxf_pump_flight *f,
			   const struct ecmxf_rsp_hdr *h);
bool ecmxf_pump_sched_plan(const struct ecmxf_pump *p,
			   struct ecmxf_pump_flight *f, unsigned int slot,
			   u32 level, u32 avail, unsigned int flags);
u32 ecmxf_pump_sched_sent(struct ecmxf_pump_flight *f, unsigned int slot,
			  u64 answer_by_ns);
u32 ecmxf_pump_sched_unsent(struct ecmxf_pump_flight *f, unsigned int slot);
bool ecmxf_pump_sched_waits(const struct ecmxf_pump_sched *s,
			    const struct ecmxf_pump_flight *f,
			    unsigned int slot, u64 timeout_ns, u64 now);
int ecmxf_pump_sched_finish(struct ecmxf_pump_flight *f, unsigned int slot,
			    int status, u32 *skipped);
void ecmxf_pump_sched_cancel(struct ecmxf_pump_flight *f, unsigned int slot);
int ecmxf_pump_sched_answer(struct ecmxf_pump *p,
			    const struct ecmxf_pump_flight *f,
			    unsigned int slot, const struct ecmxf_rsp_hdr *h,
			    u32 rx_len, struct ecmxf_pump_acct *a);
void ecmxf_pump_sched_left(struct ecmxf_pump_sched *s,
			   const struct ecmxf_pump_flight *f,
			   unsigned int slot, const struct ecmxf_rsp_hdr *h,
			   int avail, struct ecmxf_pump_acct *a);
void ecmxf_pump_sched_failed(struct ecmxf_pump *p,
			     const struct ecmxf_pump_flight *f,
			     unsigned int slot, struct ecmxf_pump_acct *a);
void ecmxf_pump_est_start(struct ecmxf_pump_est *e, u64 bus_ns, u64 now);
u32 ecmxf_pump_est_cycle(struct ecmxf_pump_est *e,
			 const struct ecmxf_pump *p, u32 in_flight, u64 now);
void ecmxf_pump_est_pushed(struct ecmxf_pump_est *e,
			   const struct ecmxf_pump_plan *pl, u32 rx_cnt,
			   u64 at, u64 cycle);
bool ecmxf_pump_est_popped(struct ecmxf_pump_est *e,
			   const struct ecmxf_pump_plan *pl,
			   const struct ecmxf_pump_result *res, u32 tx_cnt,
			   u64 at, u32 *dropped);
void ecmxf_pump_est_read(struct ecmxf_pump_est *e, u32 tx_cnt, u64 at);
void ecmxf_pump_cycle_start(struct ecmxf_pump_cycle *c, u32 level,
			    bool wkc);
bool ecmxf_pump_cycle_next(const struct ecmxf_pump *p,
			   struct ecmxf_pump_cycle *c,
			   struct ecmxf_pump_plan *pl, bool *with_wkc);
bool ecmxf_pump_cycle_answer(const struct ecmxf_pump *p,
			     struct ecmxf_pump_cycle *c,
			     struct ecmxf_pump_est *e,
			     const struct ecmxf_pump_plan *pl,
			     const struct ecmxf_pump_result *res, u32 tx_cnt,
			     u64 at, u32 *dropped);
bool ecmxf_pump_cycle_wkc_alone(const struct ecmxf_pump_cycle *c);
bool ecmxf_pump_cycle_ahead(const struct ecmxf_pump *p,
			    struct ecmxf_pump_flight *f, unsigned int slot,
			    u32 level);

#ifdef __cplusplus
}
#endif

#endif /* ECMXF_PUMP_H */
