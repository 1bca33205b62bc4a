// SPDX-License-Identifier: MIT
// What the guest benchmarks (guest-bench.cpp, guest-cyclic-bench.cpp) read
// from /proc about CPU time (their own, and the ecmxf0 link worker's), CPU
// pinning, and the exact system-call count of a piece of code (ptrace),
// by system call and by call site.
#pragma once

#include <dirent.h>
#include <linux/filter.h>
#include <linux/gpio.h>
#include <linux/seccomp.h>
#include <linux/spi/spidev.h>
#include <elf.h>
#include <link.h>
#include <sched.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/ptrace.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <sys/time.h>
#include <sys/uio.h>
#include <sys/user.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <cxxabi.h>
#include <iterator>
#include <map>
#include <optional>
#include <string_view>
#include <unordered_map>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

namespace ecmxf::ktest {

/// One synchronous ECAT_PDO_DATA_FIFO_OP for ECMXF_IOC_CMD: push @p out
/// (one output frame), pop the inputs into @p in; the command and FIFO
/// error bits cleared first (control 0xA0). @p out and @p in must outlive
/// the ioctl. (Needs <uapi/linux/ecmxf.h> included before this header.)
inline ecmxf_cmd fifoOpCmd(const std::vector<std::uint8_t> &out, std::vector<std::uint8_t> &in)
{
	ecmxf_cmd c{};
	c.hdr.code = 5; // ECAT_PDO_DATA_FIFO_OP
	c.hdr.param = 1;
	c.hdr.data[0] = 0x03;
	c.hdr.control = 0xA0;
	c.tx_ptr = reinterpret_cast<std::uintptr_t>(out.data());
	c.tx_len = static_cast<std::uint32_t>(out.size());
	c.rx_ptr = reinterpret_cast<std::uintptr_t>(in.data());
	c.rx_size = static_cast<std::uint32_t>(in.size());
	c.timeout_us = 1'000'000;
	return c;
}

/// CPU time of this process (user + system) in microseconds.
inline double cpuUs()
{
	rusage ru{};
	getrusage(RUSAGE_SELF, &ru);
	const auto us = [](const timeval &t) {
		return static_cast<double>(t.tv_sec) * 1e6 + static_cast<double>(t.tv_usec);
	};
	return us(ru.ru_utime) + us(ru.ru_stime);
}

/// Calls @p fn(pid, comm) for the tasks of /proc (comm: /proc/PID/comm)
/// until it returns true.
inline void forEachTask(const std::function<bool(long, const std::string &)> &fn)
{
	DIR *d = ::opendir("/proc");
	if (!d)
		return;
	while (dirent *e = ::readdir(d)) {
		const long pid = std::strtol(e->d_name, nullptr, 10);
		if (pid <= 0)
			continue;
		std::ifstream f("/proc/" + std::string(e->d_name) + "/comm");
		std::string name;
		if (std::getline(f, name) && fn(pid, name))
			break;
	}
	::closedir(d);
}

/// The pid of the first task whose /proc/PID/comm is @p comm, or 0.
inline long pidOf(const std::string &comm)
{
	long found = 0;
	forEachTask([&](long pid, const std::string &name) {
		if (name != comm)
			return false;
		found = pid;
		return true;
	});
	return found;
}

/// The pid of the kernel thread "ecmxf0" (the link worker), or 0.
inline long workerPid()
{
	return pidOf("ecmxf0");
}

/// Runs @p pid (0: this thread) on CPU @p cpu only; 0 or the errno.
inline int pinToCpu(long pid, unsigned cpu)
{
	cpu_set_t set;
	CPU_ZERO(&set);
	CPU_SET(cpu, &set);
	return ::sched_setaffinity(static_cast<pid_t>(pid), sizeof(set), &set) ? errno : 0;
}

/// CPU time of @p pid in microseconds (schedstat: ns on the CPU), or 0.
inline double taskCpuUs(long pid)
{
	if (!pid)
		return 0;
	std::ifstream f("/proc/" + std::to_string(pid) + "/schedstat");
	unsigned long long ns = 0;
	f >> ns;
	return static_cast<double>(ns) / 1000.0;
}

inline const char *syscallName(std::size_t nr)
{
	switch (nr) {
	case SYS_read: return "read";
	case SYS_write: return "write";
#ifdef SYS_poll // x86-64; arm64 has only ppoll
	case SYS_poll: return "poll";
#endif
	case SYS_ioctl: return "ioctl";
	case SYS_brk: return "brk";
	case SYS_mmap: return "mmap";
	case SYS_munmap: return "munmap";
	case SYS_futex: return "futex";
	case SYS_clock_gettime: return "clock_gettime";
	case SYS_clock_nanosleep: return "clock_nanosleep";
	case SYS_nanosleep: return "nanosleep";
	case SYS_ppoll: return "ppoll";
	default: return nullptr;
	}
}

/// A demangled function name made short: no return type, no parameter
/// lists, no ecmxf:: or anonymous namespace, and a lambda called through
/// std::function (inlined into the handler's _M_invoke) named by its type.
inline std::string prettyName(std::string n)
{
	constexpr std::string_view kHandler = "std::_Function_handler<";
	const auto at = [&](std::size_t i, std::string_view w) {
		return i >= w.size() && n.compare(i - w.size(), w.size(), w) == 0;
	};
	// a template function's return type: "void std::sort<...>(...)"
	const std::size_t sp = n.find(' ');
	if (sp != std::string::npos && sp < n.find_first_of("<(:"))
		n.erase(0, sp + 1);
	if (n.starts_with(kHandler)) {
		int depth = 0;
		std::size_t from = std::string::npos;
		for (std::size_t i = kHandler.size(); i < n.size(); i++) {
			const char c = n[i];
			if (c == '<' || c == '(')
				depth++;
			else if (c == '>' || c == ')') {
				if (depth == 0) {
					if (from != std::string::npos)
						n = n.substr(from, i - from);
					break;
				}
				depth--;
			} else if (c == ',' && depth == 0 && from == std::string::npos)
				from = i + 2;
		}
	}
	for (const char *pre : { "ecmxf::", "(anonymous namespace)::" })
		for (std::size_t p; (p = n.find(pre)) != std::string::npos;)
			n.erase(p, std::strlen(pre));
	// parameter lists: every (...) after a name, but the call operator's
	// "()" and a lambda's own
	std::string out;
	for (std::size_t i = 0; i < n.size(); i++) {
		if (n[i] == '(' && !at(i, "operator") && !at(i, "lambda")) {
			int depth = 0;
			std::size_t j = i;
			for (; j < n.size(); j++) {
				if (n[j] == '(')
					depth++;
				else if (n[j] == ')' && --depth == 0)
					break;
			}
			i = j;
			if (n.compare(i + 1, 6, " const") == 0)
				i += 6;
			continue;
		}
		out += n[i];
	}
	if (out.ends_with("::operator()"))
		out.erase(out.size() - 12);
	return out;
}

/// The functions of this executable (its .symtab; the guest programs are
/// static), to name the call site of a traced system call: the tracer is
/// a fork of the traced process, so the code is at the same addresses.
class CodeMap
{
public:
	CodeMap()
	{
		::dl_iterate_phdr(
			[](dl_phdr_info *info, std::size_t, void *self) -> int {
				auto &m = *static_cast<CodeMap *>(self);
				for (unsigned i = 0; i < info->dlpi_phnum; i++) {
					const ElfW(Phdr) &ph = info->dlpi_phdr[i];
					if (ph.p_type == PT_LOAD && (ph.p_flags & PF_X)) {
						m.lo_ = info->dlpi_addr + ph.p_vaddr;
						m.hi_ = m.lo_ + ph.p_memsz;
					}
				}
				m.base_ = info->dlpi_addr;
				return 1; // the executable only
			},
			this);
		std::ifstream f("/proc/self/exe", std::ios::binary);
		img_.assign(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
		const std::string &img = img_;
		if (img.size() < sizeof(ElfW(Ehdr)))
			return;
		ElfW(Ehdr) eh;
		std::memcpy(&eh, img.data(), sizeof eh);
		for (unsigned i = 0; i < eh.e_shnum; i++) {
			ElfW(Shdr) sh;
			const std::size_t off = eh.e_shoff + std::size_t{ i } * eh.e_shentsize;
			if (off + sizeof sh > img.size())
				return;
			std::memcpy(&sh, img.data() + off, sizeof sh);
			if (sh.sh_type != SHT_SYMTAB || sh.sh_link >= eh.e_shnum)
				continue;
			ElfW(Shdr) strs;
			std::memcpy(&strs, img.data() + eh.e_shoff + std::size_t{ sh.sh_link } * eh.e_shentsize, sizeof strs);
			for (std::size_t o = sh.sh_offset; o + sizeof(ElfW(Sym)) <= sh.sh_offset + sh.sh_size &&
							    o + sizeof(ElfW(Sym)) <= img.size();
			     o += sizeof(ElfW(Sym))) {
				ElfW(Sym) sym;
				std::memcpy(&sym, img.data() + o, sizeof sym);
				if (ELF64_ST_TYPE(sym.st_info) != STT_FUNC || !sym.st_value ||
				    strs.sh_offset + sym.st_name >= img.size())
					continue;
				syms_.push_back({ base_ + sym.st_value, sym.st_size, img.c_str() + strs.sh_offset + sym.st_name });
			}
		}
		std::sort(syms_.begin(), syms_.end(), [](const Sym &a, const Sym &b) { return a.addr < b.addr; });
	}

	/// @p a is in this executable's code, right behind a call instruction.
	[[nodiscard]] bool returnAddress(std::uintptr_t a) const
	{
		if (a < lo_ + 8 || a >= hi_)
			return false;
		const auto *p = reinterpret_cast<const unsigned char *>(a);
		return p[-5] == 0xE8 ||                                           // call rel32
		       (p[-2] == 0xFF && (p[-1] & 0x38) == 0x10) ||               // call *%reg, *(%reg)
		       (p[-3] == 0xFF && (p[-2] & 0x38) == 0x10) ||               // call *d8(%reg)
		       (p[-6] == 0xFF && (p[-5] & 0x38) == 0x10) ||               // call *d32(%reg), *rel(%rip)
		       (p[-7] == 0xFF && (p[-6] & 0x38) == 0x10);                 // call *d32(%reg,%idx)
	}

	/// Where the direct call (call rel32) before return address @p a
	/// goes, or 0 (another kind of call).
	[[nodiscard]] static std::uintptr_t directTarget(std::uintptr_t a)
	{
		const auto *p = reinterpret_cast<const unsigned char *>(a);
		if (p[-5] != 0xE8)
			return 0;
		std::int32_t rel = 0;
		std::memcpy(&rel, p - 4, sizeof rel);
		return static_cast<std::uintptr_t>(static_cast<std::intptr_t>(a) + rel);
	}
	/// The start and size of the function @p a is in (0, 0: none).
	[[nodiscard]] std::pair<std::uintptr_t, std::size_t> function(std::uintptr_t a) const
	{
		auto it = std::upper_bound(syms_.begin(), syms_.end(), a,
					   [](std::uintptr_t v, const Sym &s) { return v < s.addr; });
		if (it == syms_.begin() || a < lo_ || a >= hi_)
			return { 0, 0 };
		--it;
		return { it->addr, it->size };
	}
	/// Is @p a a call to the function that starts at @p callee (0: not
	/// known)? A direct call to another function is not, unless that one
	/// is small enough to be a stub that jumps on (a tail call).
	[[nodiscard]] bool callsInto(std::uintptr_t a, std::uintptr_t callee) const
	{
		const std::uintptr_t t = directTarget(a);
		if (!callee || !t || t == callee)
			return true;
		const auto [start, size] = function(t);
		return start == t && size <= 64;
	}

	/// The function @p a is in, demangled, without its parameters.
	/// (Kept per function: the tracer names every traced system call's
	/// frames, and a slow tracer slows the traced cycle.)
	[[nodiscard]] const std::string &name(std::uintptr_t a) const
	{
		static const std::string unknown = "?";
		auto it = std::upper_bound(syms_.begin(), syms_.end(), a,
					   [](std::uintptr_t v, const Sym &s) { return v < s.addr; });
		if (it == syms_.begin())
			return unknown;
		--it;
		auto [at, fresh] = names_.try_emplace(it->addr);
		if (fresh) {
			int st = 0;
			char *d = abi::__cxa_demangle(it->name, nullptr, nullptr, &st);
			at->second = prettyName(st == 0 && d ? d : it->name);
			std::free(d);
		}
		return at->second;
	}

private:
	struct Sym {
		std::uintptr_t addr;
		std::size_t size;
		const char *name;
	};
	std::uintptr_t base_ = 0, lo_ = 0, hi_ = 0;
	std::vector<Sym> syms_;
	mutable std::unordered_map<std::uintptr_t, std::string> names_;
	/// the executable's bytes: the names point into them
	std::string img_;
};

/// A project function (C++, not the C or C++ runtime's): the call site.
inline bool projectFrame(const std::string &n)
{
	return n.find("::") != std::string::npos && !n.starts_with("std::") && !n.starts_with("__gnu_cxx::") &&
	       !n.starts_with("__cxxabiv1::") && !n.starts_with("ktest::");
}

/// The system calls of a traced run by call site: "name @ site < caller".
using SiteCounts = std::map<std::string, long>;

/// A system call's name; an ioctl's with its request where the benchmarks
/// make it (the SPI transfer, the GPIO line value, the ecmxf command).
inline std::string callName(std::size_t nr, std::uint64_t arg1)
{
	if (nr == SYS_ioctl) {
		if (arg1 == SPI_IOC_MESSAGE(1))
			return "ioctl(SPI_IOC_MESSAGE)";
		if (arg1 == GPIOHANDLE_GET_LINE_VALUES_IOCTL)
			return "ioctl(GPIOHANDLE_GET_LINE_VALUES)";
	}
	const char *sn = syscallName(nr);
	return sn ? sn : "nr" + std::to_string(nr);
}

/// "call @ site < caller" of the system call @p nr that the stopped tracee
/// @p pid makes at @p ip with the stack pointer @p sp: the innermost two
/// project functions whose return addresses are on its stack (8 KiB from
/// @p sp). Each return address taken must come from a call into the
/// function of the one before (from the one that holds @p ip), where the
/// call says where it goes: a stale return address left on the stack by
/// an earlier call is skipped.
inline std::string siteKey(const CodeMap &code, pid_t pid, std::size_t nr, std::uint64_t arg1, std::uint64_t sp,
			   std::uint64_t ip)
{
	std::uintptr_t callee = code.function(ip).first;
	std::array<std::uintptr_t, 1024> stack{};
	iovec local{ stack.data(), sizeof stack };
	iovec remote{ reinterpret_cast<void *>(sp), sizeof stack };
	const ssize_t got = ::process_vm_readv(pid, &local, 1, &remote, 1, 0);
	std::string site;
	int found = 0;
	for (std::size_t i = 0; got > 0 && i < static_cast<std::size_t>(got) / 8 && found < 2; i++) {
		if (!code.returnAddress(stack[i]) || !code.callsInto(stack[i], callee))
			continue;
		callee = code.function(stack[i]).first;
		const std::string &n = code.name(stack[i]);
		if (!projectFrame(n) || (found == 1 && n == site))
			continue;
		site += found ? " < " + n : n;
		found++;
	}
	return callName(nr, arg1) + " @ " + (found ? site : std::string("?"));
}

#if defined(__x86_64__)
/// Forks a child that asks to be traced by this process and stops itself
/// (SIGSTOP): in the child it returns 0 and the caller runs what is to be
/// traced; in the parent the child's pid (or -1), which the caller waits
/// for. Standard output is flushed first, so the child repeats nothing.
inline pid_t forkTracee()
{
	std::fflush(stdout);
	const pid_t pid = ::fork();
	if (pid == 0) {
		::ptrace(PTRACE_TRACEME, 0, nullptr, nullptr);
		::raise(SIGSTOP);
	}
	return pid;
}
#endif

/// System calls counted by number, and named for the bench's lines.
struct CallTally {
	long count = 0;
	std::vector<long> byNr; ///< syscall number -> count (numbers below 1024)

	void add(std::size_t nr)
	{
		count++;
		if (nr < 1024) {
			if (byNr.size() <= nr)
				byNr.resize(nr + 1, 0);
			byNr[nr]++;
		}
	}
	/// " name=N" for each number seen, in number order.
	[[nodiscard]] std::string names() const
	{
		std::string which;
		for (std::size_t nr = 0; nr < byNr.size(); nr++) {
			if (!byNr[nr])
				continue;
			const char *name = syscallName(nr);
			which += " ";
			which += name ? name : "nr" + std::to_string(nr);
			which += "=" + std::to_string(byNr[nr]);
		}
		return which;
	}
};

/// System calls made by @p body, run in a child process traced with
/// PTRACE_SYSCALL (between two getppid() markers); @p which gets them by
/// name, @p failed the number @p body returns (its failed commands), @p
/// sites (when given) them by call site: the innermost two project
/// functions found on the stack (return addresses behind call
/// instructions, scanned from the stack pointer; a heuristic, as good as
/// a stack without frame pointers allows). -1 where that cannot be
/// counted (not x86-64).
inline long countSyscalls(const std::function<int()> &body, std::string &which, int &failed,
			  SiteCounts *sites = nullptr)
{
	failed = -1;
#if defined(__x86_64__)
	std::optional<CodeMap> code;
	if (sites)
		code.emplace();
	const pid_t pid = forkTracee();
	if (pid < 0)
		return -1;
	if (pid == 0) {
		::syscall(SYS_getppid);
		const int f = body();
		::syscall(SYS_getppid);
		::_exit(std::min(f, 255));
	}
	int st = 0;
	::waitpid(pid, &st, 0);
	::ptrace(PTRACE_SETOPTIONS, pid, nullptr, reinterpret_cast<void *>(PTRACE_O_TRACESYSGOOD | PTRACE_O_EXITKILL));
	CallTally calls;
	int markers = 0;
	bool entry = true;
	long sig = 0;
	for (;;) {
		if (::ptrace(PTRACE_SYSCALL, pid, nullptr, reinterpret_cast<void *>(sig)) < 0)
			break;
		sig = 0;
		if (::waitpid(pid, &st, 0) < 0)
			break;
		if (WIFEXITED(st)) {
			failed = WEXITSTATUS(st);
			break;
		}
		if (WIFSIGNALED(st))
			break;
		if (!WIFSTOPPED(st))
			continue;
		if (WSTOPSIG(st) == (SIGTRAP | 0x80)) {
			if (entry) {
				user_regs_struct regs{};
				::ptrace(PTRACE_GETREGS, pid, nullptr, &regs);
				if (static_cast<long>(regs.orig_rax) == SYS_getppid)
					markers++;
				else if (markers == 1) {
					const auto nr = static_cast<std::size_t>(regs.orig_rax);
					calls.add(nr);
					if (sites)
						(*sites)[siteKey(*code, pid, nr, regs.rsi, regs.rsp, regs.rip)]++;
				}
			}
			entry = !entry;
		} else {
			sig = WSTOPSIG(st); // deliver it
		}
	}
	if (failed < 0 && ::waitpid(pid, &st, 0) == pid && WIFEXITED(st))
		failed = WEXITSTATUS(st);
	which += calls.names();
	return markers >= 2 ? calls.count : -1;
#else
	(void)body;
	(void)which;
	(void)failed;
	(void)sites;
	return -1;
#endif
}

/// System calls of @p traced runs of @p cycle, each traced run followed by
/// @p stride - 1 untraced ones, in a child process: a traced cycle is
/// many times slower (a ptrace stop per system call), so tracing every
/// cycle would pile up work (frames in the chip's FIFOs) that a cycle at
/// full speed does not have; the untraced cycles between bring the
/// exchange back to its steady state. The child marks each cycle with a
/// getppid() that a seccomp filter reports to the tracer
/// (SECCOMP_RET_TRACE) also while it is not stopping at system calls.
/// @p which gets the calls by name, @p sites (when given) by call site.
/// Returns the calls of the traced cycles, or -1 (not x86-64, no
/// seccomp or PTRACE_GET_SYSCALL_INFO: Linux 5.3).
inline long countCycleSyscalls(const std::function<void()> &cycle, unsigned traced, unsigned stride,
			       std::string &which, SiteCounts *sites = nullptr)
{
#if defined(__x86_64__)
	stride = std::max(stride, 1u);
	std::optional<CodeMap> code;
	if (sites)
		code.emplace();
	const pid_t pid = forkTracee();
	if (pid < 0)
		return -1;
	if (pid == 0) {
		// getppid() -> SECCOMP_RET_TRACE, everything else allowed
		std::array<sock_filter, 4> prog{ {
			{ BPF_LD | BPF_W | BPF_ABS, 0, 0, static_cast<std::uint32_t>(offsetof(seccomp_data, nr)) },
			{ BPF_JMP | BPF_JEQ | BPF_K, 0, 1, static_cast<std::uint32_t>(SYS_getppid) },
			{ BPF_RET | BPF_K, 0, 0, SECCOMP_RET_TRACE },
			{ BPF_RET | BPF_K, 0, 0, SECCOMP_RET_ALLOW },
		} };
		sock_fprog fp{ static_cast<unsigned short>(prog.size()), prog.data() };
		if (::prctl(PR_SET_NO_NEW_PRIVS, 1, 0, 0, 0) != 0 ||
		    ::syscall(SYS_seccomp, SECCOMP_SET_MODE_FILTER, 0, &fp) != 0)
			::_exit(3);
		const unsigned n = traced * stride;
		for (unsigned i = 0; i < n; i++) {
			::syscall(SYS_getppid);
			cycle();
		}
		::syscall(SYS_getppid);
		::_exit(0);
	}
	int st = 0;
	::waitpid(pid, &st, 0);
	::ptrace(PTRACE_SETOPTIONS, pid, nullptr,
		 reinterpret_cast<void *>(PTRACE_O_TRACESYSGOOD | PTRACE_O_EXITKILL | PTRACE_O_TRACESECCOMP));
	CallTally calls;
	long markers = 0;
	unsigned done = 0;    // traced cycles finished
	bool tracing = false; // the cycle running now is traced
	int request = PTRACE_CONT;
	long sig = 0;
	bool ok = true;
	for (;;) {
		if (::ptrace(static_cast<__ptrace_request>(request), pid, nullptr, reinterpret_cast<void *>(sig)) < 0)
			break;
		sig = 0;
		if (::waitpid(pid, &st, 0) < 0)
			break;
		if (WIFEXITED(st)) {
			ok = WEXITSTATUS(st) == 0;
			break;
		}
		if (WIFSIGNALED(st)) {
			ok = false;
			break;
		}
		if (!WIFSTOPPED(st))
			continue;
		const bool seccompStop = (st >> 8) == (SIGTRAP | (PTRACE_EVENT_SECCOMP << 8));
		if (WSTOPSIG(st) != (SIGTRAP | 0x80) && !seccompStop) {
			sig = WSTOPSIG(st); // deliver it
			continue;
		}
		__ptrace_syscall_info info{};
		if (::ptrace(PTRACE_GET_SYSCALL_INFO, pid, reinterpret_cast<void *>(sizeof info), &info) <= 0) {
			ok = false;
			::kill(pid, SIGKILL);
			continue;
		}
		if (info.op == PTRACE_SYSCALL_INFO_SECCOMP) {
			// a cycle's marker: the last one ends, the next begins
			if (tracing)
				done++;
			markers++;
			tracing = done < traced && (markers - 1) % stride == 0;
			request = tracing ? PTRACE_SYSCALL : PTRACE_CONT;
			continue;
		}
		if (info.op == PTRACE_SYSCALL_INFO_ENTRY && tracing && info.entry.nr != SYS_getppid) {
			const auto nr = static_cast<std::size_t>(info.entry.nr);
			calls.add(nr);
			if (sites)
				(*sites)[siteKey(*code, pid, nr, info.entry.args[1], info.stack_pointer,
						 info.instruction_pointer)]++;
		}
		request = tracing ? PTRACE_SYSCALL : PTRACE_CONT;
	}
	which += calls.names();
	return ok && done == traced ? calls.count : -1;
#else
	(void)cycle;
	(void)traced;
	(void)stride;
	(void)which;
	(void)sites;
	return -1;
#endif
}

} // namespace ecmxf::ktest
