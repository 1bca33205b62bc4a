// SPDX-License-Identifier: MIT
/*
 * fuzz_response.cpp - libFuzzer target: everything the chip can send us
 *
 * Part (a), the codec: the input, and prefixes of it, are decoded as a
 * response packet with every check type; a copy with the frame repaired
 * (start word, end word, check word) must decode, and every valid packet
 * must re-encode to the same bytes.
 *
 * Part (b), the exchange engine, driven by the same input read as:
 *
 *   [0..1]  le16: data size = 32 + v % 1377
 *   [2]     bits 1-0 check type; bits 7-2 retry bound (0 keeps the default)
 *   [3]     bits 3-0 number of script operations (% 13), bit 7 run the
 *           script again when it ends; then 4 bytes per operation:
 *           kind, a, b, c (see run_op() and submit())
 *   then, per exchange: ctl, aux, and 24 header bytes of the response
 *   (the whole packet when ctl bit 4 is set; none when aux bit 7 is set:
 *   the previous response's header again), zero-padded at the end:
 *     ctl bits 1-0  clock step: aux us / aux ms / aux * 100 ms / to the
 *                   next deadline or hold-off end (aux bit 0: 1 ns early)
 *     ctl bit 2     repair the frame (start, end and check word)
 *     ctl bit 3     answer the packet sent one exchange earlier with its
 *                   (index, code), as the chip does (INFO_UPDATE for a
 *                   repeated (index, code))
 *     ctl bit 4     whole packet from the input (else a data pattern)
 *     ctl bit 5     clamp the length field into the data section
 *     ctl bit 6     run the next script operation first (it also runs
 *                   whenever the engine is idle)
 *     ctl bit 7     repair with the previous check type, not the current;
 *                   and first call ecmxf_engine_next() with wrong sizes
 *   At most kMaxSteps exchanges run, whatever the input.
 *
 * Invariants (abort() on violation): xfer->rx_len <= rx_size; status is
 * -EINPROGRESS exactly while the engine holds the xfer, otherwise one of
 * the documented final codes; never cur == async; nothing survives past
 * its deadline; ecmxf_engine_next() succeeds for the right size (-EAGAIN
 * exactly before the hold-off ends, -EINVAL for a wrong size) and its
 * packet decodes as a command with the check type it must be sent in
 * (fixed for the first send of SPI_RECONFIG_OP; the old type for
 * CRC_TYPE_SET and WARM_RESET, which switch only after it), carries the
 * submitted header and data, a fresh (index, code) for a first send and
 * the previous packet's for a re-send.  The rx buffers are exactly-sized
 * heap blocks, so AddressSanitizer sees every overrun.
 */
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <vector>

#include "ecmxf-proto.h"
#include "fuzz.h"

const char *ecmxf_fuzz_context = nullptr;

namespace {

/* ECMXF_FUZZ_TRACE=1 in the environment: narrate what the input does. */
bool tracing()
{
	static const bool on = std::getenv("ECMXF_FUZZ_TRACE") != nullptr;

	return on;
}

#define TRACE(...)                                                      \
	do {                                                            \
		if (tracing())                                          \
			std::fprintf(stderr, __VA_ARGS__);              \
	} while (0)

/* Bound on exchanges per input, whatever the input says. */
constexpr unsigned kMaxSteps = 1024;
constexpr unsigned kMaxOps = 12;
/* Finished xfers kept (and checked) after they finish; older ones are
 * freed, so ASan reports the engine touching one. */
constexpr size_t kKeepSlots = 24;

/*
 * Byte loops in this file cost more than the code under test once the
 * fuzzer instruments every comparison: use memcmp/memcpy, which ASan
 * range-checks as a whole.
 */
const u8 kZeros[ECMXF_PKT_MAX] = {};
u8 g_scratch[ECMXF_PKT_MAX];

bool all_zero(const u8 *p, size_t n)
{
	return n == 0 || std::memcmp(p, kZeros, n) == 0;
}

/* The data pattern of responses that do not take it from the input. */
const u8 *pattern()
{
	static const auto *pat = [] {
		static u8 buf[ECMXF_DATA_MAX + 64];

		for (size_t i = 0; i < sizeof(buf); i++)
			buf[i] = static_cast<u8>(i * 7u + 3u);
		return buf;
	}();
	return pat;
}

const ecmxf_check kChecks[] = { ECMXF_CHECK_FIXED, ECMXF_CHECK_CRC8,
				ECMXF_CHECK_CCITT, ECMXF_CHECK_CRC32 };

u16 get_le16(const u8 *p)
{
	return static_cast<u16>(p[0] | (p[1] << 8));
}

u32 get_le32(const u8 *p)
{
	return static_cast<u32>(p[0]) | (static_cast<u32>(p[1]) << 8) |
	       (static_cast<u32>(p[2]) << 16) | (static_cast<u32>(p[3]) << 24);
}

void put_le16(u8 *p, u16 v)
{
	p[0] = static_cast<u8>(v);
	p[1] = static_cast<u8>(v >> 8);
}

void put_le32(u8 *p, u32 v)
{
	for (int i = 0; i < 4; i++)
		p[i] = static_cast<u8>(v >> (8 * i));
}

bool pkt_len_valid(size_t len)
{
	return len >= ECMXF_PKT_SIZE(ECMXF_DATA_MIN) && len <= ECMXF_PKT_MAX;
}

/* Start word, check word of @check (and its coverage flag), end word. */
void repair_frame(u8 *pkt, size_t len, ecmxf_check check)
{
	size_t n = len - ECMXF_HDR_SIZE - ECMXF_TRAILER_SIZE;

	put_le32(pkt, ECMXF_START_WORD);
	put_le32(pkt + ECMXF_HDR_SIZE + n,
		 ecmxf_check_word(check, pkt, ecmxf_check_span(pkt, len, check)));
	put_le32(pkt + ECMXF_HDR_SIZE + n + 4, ECMXF_END_WORD);
}

class Reader {
public:
	Reader(const u8 *d, size_t n) : d_(d), n_(n) {}
	bool empty() const { return pos_ >= n_; }
	u8 byte() { return pos_ < n_ ? d_[pos_++] : 0; }
	u16 le16()
	{
		u8 lo = byte();
		u8 hi = byte();
		return static_cast<u16>(lo | (hi << 8));
	}
	/* @len bytes into @dst; zeros once the input runs out. */
	void fill(u8 *dst, size_t len)
	{
		size_t k = n_ - pos_ < len ? n_ - pos_ : len;

		if (k)
			std::memcpy(dst, d_ + pos_, k);
		if (k < len)
			std::memset(dst + k, 0, len - k);
		pos_ += k;
	}

private:
	const u8 *d_;
	size_t n_;
	size_t pos_ = 0;
};

/* ------------------------------------------------------------------ */
/* Part (a): the codec                                                 */
/* ------------------------------------------------------------------ */

void check_valid_rsp(const u8 *pkt, size_t len, ecmxf_check check,
		     const ecmxf_rsp_hdr &h, const u8 *data)
{
	size_t n = len - ECMXF_HDR_SIZE - ECMXF_TRAILER_SIZE;

	FUZZ_ASSERT(pkt_len_valid(len));
	FUZZ_ASSERT(data == pkt + ECMXF_HDR_SIZE);
	FUZZ_ASSERT(h.len <= n);
	FUZZ_ASSERT(data + h.len <= pkt + len - ECMXF_TRAILER_SIZE);
	/* read all hdr.len bytes: ASan checks the whole range */
	if (h.len) {
		std::memcpy(g_scratch, data, h.len);
		__asm__ __volatile__("" : : "r"(g_scratch) : "memory");
	}

	FUZZ_ASSERT(get_le32(pkt) == ECMXF_START_WORD);
	FUZZ_ASSERT(get_le32(pkt + len - 4) == ECMXF_END_WORD);
	FUZZ_ASSERT(get_le32(pkt + len - 8) != ECMXF_NOT_READY_WORD);
	FUZZ_ASSERT(get_le32(pkt + len - 8) ==
		    ecmxf_check_word(check, pkt,
				     ecmxf_check_span(pkt, len, check)));
	if (!(check & ECMXF_CHECK_COVER_VALID))
		FUZZ_ASSERT(ecmxf_check_span(pkt, len, check) == len - 8);
	FUZZ_ASSERT(h.crc_err_cnt == pkt[0x04] && h.wkc_err_cnt == pkt[0x05]);
	FUZZ_ASSERT(h.tx_fifo_cnt == pkt[0x06] && h.rx_fifo_cnt == pkt[0x07]);
	FUZZ_ASSERT(h.ecat_state == pkt[0x08] && h.err_status == pkt[0x09]);
	FUZZ_ASSERT(h.ecm_status == pkt[0x0A] && h.index == pkt[0x0B]);
	FUZZ_ASSERT(h.code == pkt[0x0C] && h.ret == pkt[0x0D]);
	FUZZ_ASSERT(h.len == get_le16(pkt + 0x0E));
	FUZZ_ASSERT(h.int_flags == get_le32(pkt + 0x10));
	FUZZ_ASSERT(h.gpio_int_flag[0] == pkt[0x14] &&
		    h.gpio_int_flag[1] == pkt[0x15]);
	FUZZ_ASSERT(h.gpio_in[0] == pkt[0x16] && h.gpio_in[1] == pkt[0x17]);

	/* the chip's encoder gives back the same bytes */
	std::vector<u8> re(len);
	FUZZ_ASSERT(ecmxf_encode_rsp(re.data(), len, check, &h, data, n) == 0);
	FUZZ_ASSERT(std::memcmp(re.data(), pkt, len) == 0);
}

ecmxf_fault decode_one(const u8 *pkt, size_t len, ecmxf_check check)
{
	ecmxf_rsp_hdr h;
	const u8 *data = nullptr;
	ecmxf_fault f, f2;

	std::memset(&h, 0xA5, sizeof(h));
	f = ecmxf_decode_rsp(pkt, len, check, &h, &data);
	FUZZ_ASSERT(f >= ECMXF_FAULT_NONE && f < ECMXF_FAULT_COUNT);
	FUZZ_ASSERT(ecmxf_fault_name(f) != nullptr);
	FUZZ_ASSERT((ecmxf_fault_errno(f) == 0) == (f == ECMXF_FAULT_NONE));
	if (!pkt_len_valid(len))
		FUZZ_ASSERT(f == ECMXF_FAULT_SIZE);
	if (f == ECMXF_FAULT_NONE)
		check_valid_rsp(pkt, len, check, h, data);
	else
		FUZZ_ASSERT(data == nullptr);
	f2 = ecmxf_decode_rsp(pkt, len, check, nullptr, nullptr);
	FUZZ_ASSERT(f2 == f);
	return f;
}

/* The packet with its frame repaired must decode, as both directions. */
void decode_repaired(const u8 *pkt, size_t len, ecmxf_check check)
{
	size_t n = len - ECMXF_HDR_SIZE - ECMXF_TRAILER_SIZE;
	std::vector<u8> fx(pkt, pkt + len);
	ecmxf_fault expect, f;
	ecmxf_cmd_hdr ch;
	const u8 *data = nullptr;

	repair_frame(fx.data(), len, check);
	if (get_le32(fx.data() + len - 8) == ECMXF_NOT_READY_WORD)
		expect = ECMXF_FAULT_NOT_READY;
	else if (get_le16(fx.data() + 0x0E) > n)
		expect = ECMXF_FAULT_LENGTH;
	else
		expect = ECMXF_FAULT_NONE;
	FUZZ_ASSERT(decode_one(fx.data(), len, check) == expect);

	f = ecmxf_decode_cmd(fx.data(), len, check, &ch, &data);
	if (expect == ECMXF_FAULT_NOT_READY) {
		FUZZ_ASSERT(f == ECMXF_FAULT_NOT_READY);
		return;
	}
	/* a command's length field is not checked against the section */
	FUZZ_ASSERT(f == ECMXF_FAULT_NONE);
	FUZZ_ASSERT(data == fx.data() + ECMXF_HDR_SIZE);
	FUZZ_ASSERT(ch.len == get_le16(fx.data() + 0x0E));
	std::vector<u8> re(len);
	FUZZ_ASSERT(ecmxf_encode_cmd(re.data(), len, check, &ch, data, n) == 0);
	FUZZ_ASSERT(std::memcmp(re.data(), fx.data(), len) == 0);
}

void fuzz_codec(const u8 *in, size_t size)
{
	size_t lens[3];

	lens[0] = size;
	lens[1] = size >= 2 ? get_le16(in + size - 2) % (size + 1) : 0;
	lens[2] = size > ECMXF_PKT_MAX ? ECMXF_PKT_MAX : size;

	for (size_t len : lens) {
		/* an exactly-sized copy: ASan sees any read past @len */
		std::unique_ptr<u8[]> pkt(new u8[len ? len : 1]);

		if (len)
			std::memcpy(pkt.get(), in, len);
		for (ecmxf_check check : kChecks) {
			decode_one(pkt.get(), len, check);
			if (pkt_len_valid(len))
				decode_repaired(pkt.get(), len, check);
			/* the example host code's CRC coverage */
			const auto valid = static_cast<ecmxf_check>(
				check | ECMXF_CHECK_COVER_VALID);
			decode_one(pkt.get(), len, valid);
			if (pkt_len_valid(len))
				decode_repaired(pkt.get(), len, valid);
		}
	}
	for (ecmxf_check check : kChecks)
		FUZZ_ASSERT(ecmxf_decode_rsp(nullptr, 0, check, nullptr,
					     nullptr) == ECMXF_FAULT_SIZE);
}

/* ------------------------------------------------------------------ */
/* Part (b): the exchange engine                                       */
/* ------------------------------------------------------------------ */

struct Slot {
	ecmxf_xfer x;
	ecmxf_cmd_hdr orig;		/* the header as submitted */
	std::unique_ptr<u8[]> tx;	/* exactly tx_len bytes */
	std::unique_ptr<u8[]> rx;	/* exactly rx_size bytes */
};

struct Sent {
	u8 index;
	u8 code;
};

class EngineFuzz {
public:
	explicit EngineFuzz(Reader &rd) : rd_(rd) {}
	void run();

private:
	void build_codes();
	void run_op();
	void submit(u8 code, u8 param, u8 a, u8 b, u8 c, u16 len);
	void check_all();
	bool holds(const ecmxf_xfer *x) const
	{
		return e_.cur == x || e_.nxt == x || e_.async == x;
	}
	void exchange(u8 ctl, u8 aux);

	Reader &rd_;
	ecmxf_engine e_;
	u64 now_ = 1000;
	std::vector<std::unique_ptr<Slot>> slots_;
	std::vector<u8> ops_;
	size_t op_pos_ = 0;
	bool loop_ops_ = false;
	std::vector<u8> last_hdr_;	/* header of the previous response */
	std::vector<u8> imm_codes_, async_codes_;
	std::vector<Sent> sent_;
};

void EngineFuzz::build_codes()
{
	size_t count = 0;
	const ecmxf_cmd_info *t = ecmxf_cmd_table(&count);

	FUZZ_ASSERT(t && count);
	for (size_t i = 0; i < count; i++) {
		FUZZ_ASSERT(ecmxf_cmd_lookup(t[i].code) == &t[i]);
		if (ecmxf_cmd_is_async(t[i].code, 0))
			async_codes_.push_back(t[i].code);
		else
			imm_codes_.push_back(t[i].code);
	}
}

/* Every final status the engine documents. */
bool final_status(int s)
{
	switch (s) {
	case 0:
	case -ETIMEDOUT:
	case -EBADMSG:
	case -EPROTO:
	case -EIO:
	case -EBUSY:
	case -EREMOTEIO:
	case -ECONNRESET:
	case -EMSGSIZE:
	case -ECANCELED:
		return true;
	default:
		return false;
	}
}

/*
 * Submit a command built from the operation's bytes.  c selects the
 * buffers: bits 2-0 rx (none, a zero-sized block, 1, 8, 20, 112, the data
 * section, 1408 bytes), bits 5-3 tx_len (0, 1, 4, 24, half or all of the
 * data section, one byte too many, 0), bit 6 a short timeout (50 us +
 * b * 40 us), bit 7 GPIO outputs valid; a bit 7 sets ECMXF_XF_NO_AUTO_CLEAR.
 */
void EngineFuzz::submit(u8 code, u8 param, u8 a, u8 b, u8 c, u16 len)
{
	static const u16 rx_sizes[] = { 0, 0, 1, 8, 20, 112, 0xFFFF, 1408 };
	auto s = std::make_unique<Slot>();
	ecmxf_xfer &x = s->x;
	size_t n = e_.data_size;
	u16 rx_size, tx_len;
	bool could, ok_args;
	int r;

	std::memset(&x, 0, sizeof(x));
	x.hdr.data[0] = a;
	x.hdr.data[1] = b;
	x.hdr.data[2] = c;
	x.hdr.data[3] = static_cast<u8>(a ^ c);
	x.hdr.reserved = static_cast<u16>((c & 0x80) ? ECMXF_RSV_GPIO_OUT : 0);
	x.hdr.control = static_cast<u8>(b & ECMXF_CTL_REFRESH_STATE);
	x.hdr.code = code;
	x.hdr.param = param;
	x.hdr.len = len;
	x.hdr.int_clear = (c & 0x01) ? ECMXF_INT_ECAT_PKT : 0;
	x.hdr.gpio_out[0] = a;
	x.hdr.gpio_out[1] = b;

	/* rx: none, a zero-sized block, or exactly rx_size bytes */
	unsigned rsel = c & 7u;
	rx_size = rx_sizes[rsel] == 0xFFFF ? static_cast<u16>(n) : rx_sizes[rsel];
	if (rsel != 0) {
		s->rx.reset(new u8[rx_size]);
		x.rx_buf = s->rx.get();
		x.rx_size = rx_size;
	}

	static const unsigned tx_sel[] = { 0, 1, 4, 24, 1000, 2000, 2001, 0 };
	unsigned t = tx_sel[(c >> 3) & 7u];
	if (t == 1000)
		t = static_cast<unsigned>(n / 2);
	else if (t == 2000)
		t = static_cast<unsigned>(n);
	else if (t == 2001)
		t = static_cast<unsigned>(n + 1);	/* -EMSGSIZE */
	tx_len = static_cast<u16>(t);
	if (tx_len) {
		s->tx.reset(new u8[tx_len]);
		for (unsigned i = 0; i < tx_len; i++)
			s->tx[i] = static_cast<u8>(i * 7u + a + 1u);
		x.tx_data = s->tx.get();
		x.tx_len = tx_len;
	}
	x.timeout_us = (c & 0x40) ? 50u + b * 40u : 0u;
	x.flags = (a & 0x80) ? ECMXF_XF_NO_AUTO_CLEAR : 0;
	s->orig = x.hdr;

	could = ecmxf_engine_can_submit(&e_, &x);
	ok_args = x.tx_len <= e_.data_size &&
		  !(code == ECMXF_CMD_SPI_RECONFIG_OP &&
		    !ecmxf_data_size_valid(len)) &&
		  /* the data must also fit the format they switch to */
		  !(code == ECMXF_CMD_SPI_RECONFIG_OP && x.tx_len > len) &&
		  !(code == ECMXF_CMD_WARM_RESET && x.tx_len > ECMXF_DATA_DEFAULT) &&
		  !(code == ECMXF_CMD_CRC_TYPE_SET && param > ECMXF_CHECK_CRC32);
	r = ecmxf_engine_submit(&e_, &x, now_);
	TRACE("submit code %u param %u len %u tx %u rx %s%u timeout_us %u: %d\n",
	      code, param, len, x.tx_len, x.rx_buf ? "" : "none/", x.rx_size,
	      x.timeout_us, r);
	FUZZ_ASSERT(r == 0 || r == -EBUSY || r == -EINVAL || r == -EMSGSIZE);
	FUZZ_ASSERT((r == 0) == (could && ok_args));
	if (r == -EMSGSIZE)
		FUZZ_ASSERT(x.tx_len > e_.data_size ||
			    (code == ECMXF_CMD_SPI_RECONFIG_OP && x.tx_len > len) ||
			    (code == ECMXF_CMD_WARM_RESET && x.tx_len > ECMXF_DATA_DEFAULT));
	if (r == 0) {
		FUZZ_ASSERT((e_.cur == &x || e_.nxt == &x) &&
			    x.status == -EINPROGRESS);
		FUZZ_ASSERT(x.rx_len == 0);
		FUZZ_ASSERT(x.async == ecmxf_cmd_is_async(code, param));
		if (slots_.size() >= kKeepSlots) {
			for (auto it = slots_.begin(); it != slots_.end(); ++it) {
				if (!holds(&(*it)->x)) {
					slots_.erase(it);
					break;
				}
			}
		}
		slots_.push_back(std::move(s));
	}
}

/*
 * One script operation: kind, a, b, c.  kind bits 2-0: 0 an immediate
 * command, 1 an async one (from the command table, by a), 2 a command that
 * changes the link (a: SPI_RECONFIG_OP to 32 + (b | c << 8) % 1377 bytes
 * (any value when kind bit 7 is set), CRC_TYPE_SET b, WARM_RESET,
 * ASYNCCMD_RESET), 3 code a with parameter b, 4 cancel one of the
 * submitted xfers, 5 clear_errors, 6 clear_ints, 7 cancel the current
 * (a odd: the async) command.
 */
void EngineFuzz::run_op()
{
	if (op_pos_ + 4 > ops_.size()) {
		if (!loop_ops_ || ops_.empty())
			return;
		op_pos_ = 0;		/* the script runs again */
	}
	u8 kind = ops_[op_pos_], a = ops_[op_pos_ + 1];
	u8 b = ops_[op_pos_ + 2], c = ops_[op_pos_ + 3];
	op_pos_ += 4;

	TRACE("op kind %u a %u b %u c %u\n", kind & 7u, a, b, c);
	switch (kind & 7u) {
	case 0:		/* an immediate command */
		submit(imm_codes_[a % imm_codes_.size()], b, a, b, c,
		       static_cast<u16>(b));
		break;
	case 1:		/* an async command */
		submit(async_codes_[a % async_codes_.size()],
		       static_cast<u8>(b & 0x7F), a, b, c, static_cast<u16>(b));
		break;
	case 2:		/* a command that changes the link */
		switch (a & 3u) {
		case 0:
			submit(ECMXF_CMD_SPI_RECONFIG_OP, 0, a, b, c,
			       static_cast<u16>((kind & 0x80) ?
						(b | (c << 8)) :
						32 + (b | (c << 8)) % 1377));
			break;
		case 1:
			submit(ECMXF_CMD_CRC_TYPE_SET,
			       static_cast<u8>((kind & 0x80) ? b : b & 3u), a,
			       b, c, 0);
			break;
		case 2:
			submit(ECMXF_CMD_WARM_RESET, 0, a, b, c, 0);
			break;
		default:
			submit(ECMXF_CMD_ASYNCCMD_RESET, b, a, b, c, 0);
			break;
		}
		break;
	case 3:		/* any code at all */
		submit(a, b, a, b, c, static_cast<u16>(c));
		break;
	case 4:		/* cancel one of ours, perhaps a finished one */
		if (!slots_.empty()) {
			Slot &s = *slots_[a % slots_.size()];
			bool held = holds(&s.x);
			int r = ecmxf_engine_cancel(&e_, &s.x);

			FUZZ_ASSERT(r == (held ? 0 : -ENOENT));
			if (held)
				FUZZ_ASSERT(s.x.status == -ECANCELED);
			FUZZ_ASSERT(!holds(&s.x));
		} else {
			FUZZ_ASSERT(ecmxf_engine_cancel(&e_, nullptr) ==
				    -ENOENT);
		}
		break;
	case 5:
		ecmxf_engine_clear_errors(&e_, a);
		break;
	case 6:
		ecmxf_engine_clear_ints(&e_, static_cast<u32>(a) << 24 | b, c,
					static_cast<u8>(a ^ c));
		break;
	default: {	/* cancel whatever the engine holds */
		ecmxf_xfer *x = (a & 1) ? e_.async : e_.cur;

		if (x) {
			FUZZ_ASSERT(ecmxf_engine_cancel(&e_, x) == 0);
			FUZZ_ASSERT(x->status == -ECANCELED);
		}
		break;
	}
	}
	check_all();
}

void EngineFuzz::check_all()
{
	FUZZ_ASSERT(!(e_.cur && e_.cur == e_.async));
	FUZZ_ASSERT(!(e_.nxt && (e_.nxt == e_.cur || e_.nxt == e_.async)));
	FUZZ_ASSERT(!e_.nxt || e_.cur);	/* the younger moves up */
	FUZZ_ASSERT(ecmxf_engine_idle(&e_) ==
		    (!e_.cur && !e_.nxt && !e_.async));
	FUZZ_ASSERT(ecmxf_data_size_valid(e_.data_size));
	FUZZ_ASSERT(e_.cover <= ECMXF_COVER_VALID);
	FUZZ_ASSERT(e_.check <= ECMXF_CHECK_CRC32 &&
		    e_.prev_check <= ECMXF_CHECK_CRC32);
	FUZZ_ASSERT(ecmxf_engine_pkt_size(&e_) ==
		    ECMXF_PKT_SIZE(e_.data_size));
	if (e_.async)
		FUZZ_ASSERT(e_.async->async);
	for (auto &sp : slots_) {
		const ecmxf_xfer &x = sp->x;

		FUZZ_ASSERT(x.rx_len <= x.rx_size);
		if (holds(&x))
			FUZZ_ASSERT(x.status == -EINPROGRESS);
		else
			FUZZ_ASSERT(final_status(x.status));
		if (x.status == -EMSGSIZE) {
			FUZZ_ASSERT(x.rx_buf && x.rsp.len > x.rx_size);
			FUZZ_ASSERT(x.rx_len == x.rx_size);
		}
	}
}

void EngineFuzz::exchange(u8 ctl, u8 aux)
{
	const size_t len = ecmxf_engine_pkt_size(&e_);
	const size_t n = len - ECMXF_HDR_SIZE - ECMXF_TRAILER_SIZE;
	std::vector<u8> tx(len), rsp(len);
	/*
	 * Which command the packet carries is read back after
	 * ecmxf_engine_next() (the engine may give up on one that can no
	 * longer be polled); the rules are checked below: a first send never
	 * repeats the previous (index, code), a re-send always does.
	 */
	ecmxf_xfer *x = nullptr;
	bool first = false, info = false;
	ecmxf_xfer *const cur0 = e_.cur, *const nxt0 = e_.nxt;
	/*
	 * While a CRC is in force and its coverage unknown, a new command
	 * waits for INFO_UPDATE probes (bounded), which carry the whole data
	 * section as length (protocol-core.rst, "Firmware variants")
	 */
	const bool cover_unknown = e_.check != ECMXF_CHECK_FIXED &&
				   e_.cover == ECMXF_COVER_UNKNOWN;
	const unsigned crcset_tries = e_.crcset_tries;
	bool had_last = e_.last_valid;
	u8 last_index = e_.last_index, last_code = e_.last_code;
	unsigned ck = e_.check;
	if (ck != ECMXF_CHECK_FIXED && e_.cover == ECMXF_COVER_VALID)
		ck |= ECMXF_CHECK_COVER_VALID;
	ecmxf_check check = static_cast<ecmxf_check>(ck);
	const u16 info_len = cover_unknown ? static_cast<u16>(n) : 0;
	Slot *slot = nullptr;
	ecmxf_cmd_hdr ch;
	const u8 *data = nullptr;
	int r;


	/* a wrong size never builds a packet */
	if (ctl & 0x80) {
		std::vector<u8> bad(len - 1);

		FUZZ_ASSERT(ecmxf_engine_next(&e_, now_, bad.data(),
					      bad.size()) == -EINVAL);
		FUZZ_ASSERT(ecmxf_engine_next(&e_, now_, nullptr, len) ==
			    -EINVAL);
	}

	const u64 not_before = ecmxf_engine_not_before(&e_);
	r = ecmxf_engine_next(&e_, now_, tx.data(), len);
	if (now_ < not_before) {
		FUZZ_ASSERT(r == -EAGAIN);
		FUZZ_ASSERT(e_.cur == cur0 && e_.nxt == nxt0);
		ecmxf_engine_poll_time(&e_, now_);
		check_all();
		return;
	}
	TRACE("t=%llu next(%zu B, check %u): %d\n",
	      static_cast<unsigned long long>(now_), len, e_.check, r);
	FUZZ_ASSERT(r == 0);

	for (ecmxf_xfer *k : { e_.cur, e_.nxt })
		/* a WARM_RESET already sent is polled with INFO_UPDATE */
		if (k && k->last_seq == e_.seq &&
		    !(k->hdr.code == ECMXF_CMD_WARM_RESET &&
		      k->sent_seq != e_.seq))
			x = k;
	first = x && x->sent_seq == e_.seq;
	/* WARM_RESET is polled with INFO_UPDATE, never re-sent */
	info = !x;
	if (first && x->hdr.code == ECMXF_CMD_SPI_RECONFIG_OP)
		check = ECMXF_CHECK_FIXED;
	/* a CRC_TYPE_SET the chip did not take: every other try fixed */
	if (first && x->hdr.code == ECMXF_CMD_CRC_TYPE_SET &&
	    (crcset_tries & 1))
		check = ECMXF_CHECK_FIXED;
	/* its re-sends carry the whole section while coverage is unknown */
	const bool crcset_resend = !info && !first &&
				   x->hdr.code == ECMXF_CMD_CRC_TYPE_SET &&
				   cover_unknown;
	for (auto &sp : slots_)
		if (&sp->x == x)
			slot = sp.get();
	FUZZ_ASSERT(!x || slot);

	/* the packet: right check type, right header, right data */
	FUZZ_ASSERT(ecmxf_decode_cmd(tx.data(), len, check, &ch, &data) ==
		    ECMXF_FAULT_NONE);
	FUZZ_ASSERT(data == tx.data() + ECMXF_HDR_SIZE);
	FUZZ_ASSERT(e_.last_valid && e_.last_index == ch.index &&
		    e_.last_code == ch.code);
	if (info) {
		FUZZ_ASSERT(ch.code == ECMXF_CMD_INFO_UPDATE_OP);
		FUZZ_ASSERT(ch.param == 0 && ch.len == info_len &&
			    ch.reserved == 0);
		if (had_last)
			FUZZ_ASSERT(ch.index == last_index);
		FUZZ_ASSERT(all_zero(data, n));
	} else {
		const ecmxf_cmd_hdr &o = slot->orig;

		FUZZ_ASSERT(ch.code == o.code && ch.param == o.param);
		FUZZ_ASSERT(ch.len == (crcset_resend ? n : o.len) &&
			    ch.reserved == o.reserved);
		FUZZ_ASSERT(std::memcmp(ch.data, o.data, 4) == 0);
		FUZZ_ASSERT(std::memcmp(ch.gpio_out, o.gpio_out, 2) == 0);
		FUZZ_ASSERT(ch.index == x->hdr.index);
		if (first) {
			/* a new command: never the previous (index, code) */
			FUZZ_ASSERT(!had_last || ch.index != last_index ||
				    ch.code != last_code);
			FUZZ_ASSERT((ch.control & o.control) == o.control);
			FUZZ_ASSERT((ch.int_clear & o.int_clear) == o.int_clear);
		} else {
			/* a re-send polls: the same (index, code) again */
			FUZZ_ASSERT(had_last && ch.index == last_index &&
				    ch.code == last_code);
			FUZZ_ASSERT(ch.control == 0 && ch.int_clear == 0);
			FUZZ_ASSERT(ch.gpio_int_clear[0] == 0 &&
				    ch.gpio_int_clear[1] == 0);
		}
		FUZZ_ASSERT(x->tx_len <= n);
		if (x->tx_len)
			FUZZ_ASSERT(std::memcmp(data, slot->tx.get(),
						x->tx_len) == 0);
		FUZZ_ASSERT(all_zero(data + x->tx_len, n - x->tx_len));
		FUZZ_ASSERT(ecmxf_engine_sent(&e_, x));
	}
	sent_.push_back({ ch.index, ch.code });
	check_all();

	/* the response of the same exchange, in the same size */
	if (ctl & 0x10) {
		rd_.fill(rsp.data(), len);
	} else {
		if ((aux & 0x80) && !last_hdr_.empty())	/* as last time */
			std::memcpy(rsp.data(), last_hdr_.data(), ECMXF_HDR_SIZE);
		else
			rd_.fill(rsp.data(), ECMXF_HDR_SIZE);
		std::memcpy(rsp.data() + ECMXF_HDR_SIZE, pattern() + aux % 64u, n);
	}
	if ((ctl & 0x08) && sent_.size() >= 2) {
		const Sent &p = sent_[sent_.size() - 2];
		bool again = sent_.size() >= 3 &&
			     sent_[sent_.size() - 3].index == p.index &&
			     sent_[sent_.size() - 3].code == p.code;

		rsp[0x0B] = p.index;
		rsp[0x0C] = again ? u8{ ECMXF_CMD_INFO_UPDATE_OP } : p.code;
	}
	if (ctl & 0x20)
		put_le16(rsp.data() + 0x0E,
			 static_cast<u16>(get_le16(rsp.data() + 0x0E) % (n + 1)));
	if (ctl & 0x04)
		/* aux bit 6: the example host code's CRC coverage */
		repair_frame(rsp.data(), len,
			     static_cast<ecmxf_check>(((ctl & 0x80) ?
						       e_.prev_check :
						       e_.check) |
						      ((aux & 0x40) ?
						       unsigned{ ECMXF_CHECK_COVER_VALID } :
						       0u)));
	const u8 cover_before = e_.cover;

	std::vector<u16> rx_before;
	for (auto &sp : slots_)
		rx_before.push_back(sp->x.rx_len);

	last_hdr_.assign(rsp.begin(), rsp.begin() + ECMXF_HDR_SIZE);
	unsigned ev = ecmxf_engine_input(&e_, now_, rsp.data(), len);
	TRACE("  sent idx %u code %u; rsp idx %u code %u sts 0x%02x err 0x%02x "
	      "len %u -> ev 0x%x, cur %p async %p\n", ch.index, ch.code,
	      rsp[0x0B], rsp[0x0C], rsp[0x0A], rsp[0x09], get_le16(rsp.data() + 0x0E),
	      ev, static_cast<void *>(e_.cur), static_cast<void *>(e_.async));
	FUZZ_ASSERT((ev & ~0x3Fu) == 0);
	if (ev & ECMXF_EV_BAD_PACKET)
		FUZZ_ASSERT(!(ev & ECMXF_EV_HEADER));
	/* the CRC coverage is decided once and kept */
	if (cover_before != ECMXF_COVER_UNKNOWN)
		FUZZ_ASSERT(e_.cover == cover_before);
	check_all();
	/* nothing outlives its deadline */
	if (e_.cur)
		FUZZ_ASSERT(e_.cur->deadline_ns > now_);
	if (e_.nxt)
		FUZZ_ASSERT(e_.nxt->deadline_ns > now_);
	if (e_.async)
		FUZZ_ASSERT(e_.async->deadline_ns > now_);
	/* what landed in an rx buffer is this response's data section */
	for (size_t i = 0; i < slots_.size(); i++) {
		const ecmxf_xfer &sx = slots_[i]->x;

		if (sx.rx_len != rx_before[i] && sx.rx_len)
			FUZZ_ASSERT(std::memcmp(sx.rx_buf,
						rsp.data() + ECMXF_HDR_SIZE,
						sx.rx_len) == 0);
	}
}

void EngineFuzz::run()
{
	u16 v = rd_.le16();
	u8 fmt = rd_.byte();
	u8 script = rd_.byte();
	unsigned nops = (script & 0x0Fu) % (kMaxOps + 1);

	loop_ops_ = script & 0x80;

	build_codes();
	ecmxf_engine_init(&e_, 32u + v % 1377u, kChecks[fmt & 3u]);
	if (fmt >> 2)
		ecmxf_engine_set_retries(&e_, fmt >> 2);
	FUZZ_ASSERT(e_.data_size == 32u + v % 1377u);
	FUZZ_ASSERT(ecmxf_engine_idle(&e_));
	FUZZ_ASSERT(ecmxf_engine_deadline(&e_) == ~u64{ 0 });
	for (unsigned i = 0; i < nops * 4; i++)
		ops_.push_back(rd_.byte());

	for (unsigned step = 0; step < kMaxSteps && !rd_.empty(); step++) {
		u8 ctl = rd_.byte();
		u8 aux = rd_.byte();
		u64 before = now_;

		if ((ctl & 0x40) || ecmxf_engine_idle(&e_))
			run_op();

		switch (ctl & 3u) {
		case 0:
			now_ += aux * 1000ull;
			break;
		case 1:
			now_ += aux * 1000000ull;
			break;
		case 2:
			now_ += aux * 100000000ull;
			break;
		default: {
			u64 d = ecmxf_engine_deadline(&e_);
			u64 t = d != ~u64{ 0 } ? d : ecmxf_engine_not_before(&e_);

			if (t > now_)
				now_ = t - (aux & 1u);
			break;
		}
		}
		FUZZ_ASSERT(now_ >= before);
		exchange(ctl, aux);
	}
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	fuzz_codec(data, size);

	Reader rd(data, size);
	EngineFuzz ef(rd);
	ef.run();
	return 0;
}
