#pragma once
/// @file field_coverage.hpp
/// Tests that a config struct's field list (`VisitFields`) misses none of its members: every
/// member of the struct, and of each struct member within it, must hold a field the list visits,
/// unless it is named as no field. A member added to a struct and not to its list fails the test.
/// Members are found by aggregate initialisation and structured bindings (C++17, no reflection):
/// the config structs are aggregates.

#include <cstddef>
#include <optional>
#include <string>
#include <type_traits>
#include <typeinfo>
#include <utility>
#include <vector>

namespace dorado::testing {
namespace detail {

template <typename T>
struct IsOptional : std::false_type {};
template <typename T>
struct IsOptional<std::optional<T>> : std::true_type {};

/// Converts to any member type (never called: only in unevaluated aggregate initialisation).
struct AnyMember {
    // An optional member is built from AnyMember by its own converting constructor.
    template <typename T, typename = std::enable_if_t<!IsOptional<T>::value>>
    operator T() const;  // NOLINT(google-explicit-constructor)
};

template <typename T, typename Indices, typename = void>
struct BracesTake : std::false_type {};
template <typename T, std::size_t... I>
struct BracesTake<T, std::index_sequence<I...>, std::void_t<decltype(T{(void(I), AnyMember{})...})>>
    : std::true_type {};

}  // namespace detail

/// The number of members of aggregate @p T.
template <typename T, std::size_t N = 0>
constexpr std::size_t MemberCount() {
    if constexpr (detail::BracesTake<T, std::make_index_sequence<N + 1>>::value)
        return MemberCount<T, N + 1>();
    else
        return N;
}

/// Calls @p f with each member of aggregate @p t, in declaration order; false (and no call) for
/// a struct of more than 32 members.
template <typename T, typename F>
bool ForEachMember(T &t, F &&f) {
    constexpr std::size_t n = MemberCount<T>();
    // clang-format off
    if constexpr (n == 1) {
        auto &[m0] = t;
        f(m0);
    } else if constexpr (n == 2) {
        auto &[m0,m1] = t;
        f(m0);f(m1);
    } else if constexpr (n == 3) {
        auto &[m0,m1,m2] = t;
        f(m0);f(m1);f(m2);
    } else if constexpr (n == 4) {
        auto &[m0,m1,m2,m3] = t;
        f(m0);f(m1);f(m2);f(m3);
    } else if constexpr (n == 5) {
        auto &[m0,m1,m2,m3,m4] = t;
        f(m0);f(m1);f(m2);f(m3);f(m4);
    } else if constexpr (n == 6) {
        auto &[m0,m1,m2,m3,m4,m5] = t;
        f(m0);f(m1);f(m2);f(m3);f(m4);f(m5);
    } else if constexpr (n == 7) {
        auto &[m0,m1,m2,m3,m4,m5,m6] = t;
        f(m0);f(m1);f(m2);f(m3);f(m4);f(m5);f(m6);
    } else if constexpr (n == 8) {
        auto &[m0,m1,m2,m3,m4,m5,m6,m7] = t;
        f(m0);f(m1);f(m2);f(m3);f(m4);f(m5);f(m6);f(m7);
    } else if constexpr (n == 9) {
        auto &[m0,m1,m2,m3,m4,m5,m6,m7,m8] = t;
        f(m0);f(m1);f(m2);f(m3);f(m4);f(m5);f(m6);f(m7);f(m8);
    } else if constexpr (n == 10) {
        auto &[m0,m1,m2,m3,m4,m5,m6,m7,m8,m9] = t;
        f(m0);f(m1);f(m2);f(m3);f(m4);f(m5);f(m6);f(m7);f(m8);f(m9);
    } else if constexpr (n == 11) {
        auto &[m0,m1,m2,m3,m4,m5,m6,m7,m8,m9,m10] = t;
        f(m0);f(m1);f(m2);f(m3);f(m4);f(m5);f(m6);f(m7);f(m8);f(m9);f(m10);
    } else if constexpr (n == 12) {
        auto &[m0,m1,m2,m3,m4,m5,m6,m7,m8,m9,m10,m11] = t;
        f(m0);f(m1);f(m2);f(m3);f(m4);f(m5);f(m6);f(m7);f(m8);f(m9);f(m10);f(m11);
    } else if constexpr (n == 13) {
        auto &[m0,m1,m2,m3,m4,m5,m6,m7,m8,m9,m10,m11,m12] = t;
        f(m0);f(m1);f(m2);f(m3);f(m4);f(m5);f(m6);f(m7);f(m8);f(m9);f(m10);f(m11);f(m12);
    } else if constexpr (n == 14) {
        auto &[m0,m1,m2,m3,m4,m5,m6,m7,m8,m9,m10,m11,m12,m13] = t;
        f(m0);f(m1);f(m2);f(m3);f(m4);f(m5);f(m6);f(m7);f(m8);f(m9);f(m10);f(m11);f(m12);f(m13);
    } else if constexpr (n == 15) {
        auto &[m0,m1,m2,m3,m4,m5,m6,m7,m8,m9,m10,m11,m12,m13,m14] = t;
        f(m0);f(m1);f(m2);f(m3);f(m4);f(m5);f(m6);f(m7);f(m8);f(m9);f(m10);f(m11);f(m12);f(m13);f(m14);
    } else if constexpr (n == 16) {
        auto &[m0,m1,m2,m3,m4,m5,m6,m7,m8,m9,m10,m11,m12,m13,m14,m15] = t;
        f(m0);f(m1);f(m2);f(m3);f(m4);f(m5);f(m6);f(m7);f(m8);f(m9);f(m10);f(m11);f(m12);f(m13);f(m14);f(m15);
    } else if constexpr (n == 17) {
        auto &[m0,m1,m2,m3,m4,m5,m6,m7,m8,m9,m10,m11,m12,m13,m14,m15,m16] = t;
        f(m0);f(m1);f(m2);f(m3);f(m4);f(m5);f(m6);f(m7);f(m8);f(m9);f(m10);f(m11);f(m12);f(m13);f(m14);f(m15);f(m16);
    } else if constexpr (n == 18) {
        auto &[m0,m1,m2,m3,m4,m5,m6,m7,m8,m9,m10,m11,m12,m13,m14,m15,m16,m17] = t;
        f(m0);f(m1);f(m2);f(m3);f(m4);f(m5);f(m6);f(m7);f(m8);f(m9);f(m10);f(m11);f(m12);f(m13);f(m14);f(m15);f(m16);f(m17);
    } else if constexpr (n == 19) {
        auto &[m0,m1,m2,m3,m4,m5,m6,m7,m8,m9,m10,m11,m12,m13,m14,m15,m16,m17,m18] = t;
        f(m0);f(m1);f(m2);f(m3);f(m4);f(m5);f(m6);f(m7);f(m8);f(m9);f(m10);f(m11);f(m12);f(m13);f(m14);f(m15);f(m16);f(m17);f(m18);
    } else if constexpr (n == 20) {
        auto &[m0,m1,m2,m3,m4,m5,m6,m7,m8,m9,m10,m11,m12,m13,m14,m15,m16,m17,m18,m19] = t;
        f(m0);f(m1);f(m2);f(m3);f(m4);f(m5);f(m6);f(m7);f(m8);f(m9);f(m10);f(m11);f(m12);f(m13);f(m14);f(m15);f(m16);f(m17);f(m18);f(m19);
    } else if constexpr (n == 21) {
        auto &[m0,m1,m2,m3,m4,m5,m6,m7,m8,m9,m10,m11,m12,m13,m14,m15,m16,m17,m18,m19,m20] = t;
        f(m0);f(m1);f(m2);f(m3);f(m4);f(m5);f(m6);f(m7);f(m8);f(m9);f(m10);f(m11);f(m12);f(m13);f(m14);f(m15);f(m16);f(m17);f(m18);f(m19);f(m20);
    } else if constexpr (n == 22) {
        auto &[m0,m1,m2,m3,m4,m5,m6,m7,m8,m9,m10,m11,m12,m13,m14,m15,m16,m17,m18,m19,m20,m21] = t;
        f(m0);f(m1);f(m2);f(m3);f(m4);f(m5);f(m6);f(m7);f(m8);f(m9);f(m10);f(m11);f(m12);f(m13);f(m14);f(m15);f(m16);f(m17);f(m18);f(m19);f(m20);f(m21);
    } else if constexpr (n == 23) {
        auto &[m0,m1,m2,m3,m4,m5,m6,m7,m8,m9,m10,m11,m12,m13,m14,m15,m16,m17,m18,m19,m20,m21,m22] = t;
        f(m0);f(m1);f(m2);f(m3);f(m4);f(m5);f(m6);f(m7);f(m8);f(m9);f(m10);f(m11);f(m12);f(m13);f(m14);f(m15);f(m16);f(m17);f(m18);f(m19);f(m20);f(m21);f(m22);
    } else if constexpr (n == 24) {
        auto &[m0,m1,m2,m3,m4,m5,m6,m7,m8,m9,m10,m11,m12,m13,m14,m15,m16,m17,m18,m19,m20,m21,m22,m23] = t;
        f(m0);f(m1);f(m2);f(m3);f(m4);f(m5);f(m6);f(m7);f(m8);f(m9);f(m10);f(m11);f(m12);f(m13);f(m14);f(m15);f(m16);f(m17);f(m18);f(m19);f(m20);f(m21);f(m22);f(m23);
    } else if constexpr (n == 25) {
        auto &[m0,m1,m2,m3,m4,m5,m6,m7,m8,m9,m10,m11,m12,m13,m14,m15,m16,m17,m18,m19,m20,m21,m22,m23,m24] = t;
        f(m0);f(m1);f(m2);f(m3);f(m4);f(m5);f(m6);f(m7);f(m8);f(m9);f(m10);f(m11);f(m12);f(m13);f(m14);f(m15);f(m16);f(m17);f(m18);f(m19);f(m20);f(m21);f(m22);f(m23);f(m24);
    } else if constexpr (n == 26) {
        auto &[m0,m1,m2,m3,m4,m5,m6,m7,m8,m9,m10,m11,m12,m13,m14,m15,m16,m17,m18,m19,m20,m21,m22,m23,m24,m25] = t;
        f(m0);f(m1);f(m2);f(m3);f(m4);f(m5);f(m6);f(m7);f(m8);f(m9);f(m10);f(m11);f(m12);f(m13);f(m14);f(m15);f(m16);f(m17);f(m18);f(m19);f(m20);f(m21);f(m22);f(m23);f(m24);f(m25);
    } else if constexpr (n == 27) {
        auto &[m0,m1,m2,m3,m4,m5,m6,m7,m8,m9,m10,m11,m12,m13,m14,m15,m16,m17,m18,m19,m20,m21,m22,m23,m24,m25,m26] = t;
        f(m0);f(m1);f(m2);f(m3);f(m4);f(m5);f(m6);f(m7);f(m8);f(m9);f(m10);f(m11);f(m12);f(m13);f(m14);f(m15);f(m16);f(m17);f(m18);f(m19);f(m20);f(m21);f(m22);f(m23);f(m24);f(m25);f(m26);
    } else if constexpr (n == 28) {
        auto &[m0,m1,m2,m3,m4,m5,m6,m7,m8,m9,m10,m11,m12,m13,m14,m15,m16,m17,m18,m19,m20,m21,m22,m23,m24,m25,m26,m27] = t;
        f(m0);f(m1);f(m2);f(m3);f(m4);f(m5);f(m6);f(m7);f(m8);f(m9);f(m10);f(m11);f(m12);f(m13);f(m14);f(m15);f(m16);f(m17);f(m18);f(m19);f(m20);f(m21);f(m22);f(m23);f(m24);f(m25);f(m26);f(m27);
    } else if constexpr (n == 29) {
        auto &[m0,m1,m2,m3,m4,m5,m6,m7,m8,m9,m10,m11,m12,m13,m14,m15,m16,m17,m18,m19,m20,m21,m22,m23,m24,m25,m26,m27,m28] = t;
        f(m0);f(m1);f(m2);f(m3);f(m4);f(m5);f(m6);f(m7);f(m8);f(m9);f(m10);f(m11);f(m12);f(m13);f(m14);f(m15);f(m16);f(m17);f(m18);f(m19);f(m20);f(m21);f(m22);f(m23);f(m24);f(m25);f(m26);f(m27);f(m28);
    } else if constexpr (n == 30) {
        auto &[m0,m1,m2,m3,m4,m5,m6,m7,m8,m9,m10,m11,m12,m13,m14,m15,m16,m17,m18,m19,m20,m21,m22,m23,m24,m25,m26,m27,m28,m29] = t;
        f(m0);f(m1);f(m2);f(m3);f(m4);f(m5);f(m6);f(m7);f(m8);f(m9);f(m10);f(m11);f(m12);f(m13);f(m14);f(m15);f(m16);f(m17);f(m18);f(m19);f(m20);f(m21);f(m22);f(m23);f(m24);f(m25);f(m26);f(m27);f(m28);f(m29);
    } else if constexpr (n == 31) {
        auto &[m0,m1,m2,m3,m4,m5,m6,m7,m8,m9,m10,m11,m12,m13,m14,m15,m16,m17,m18,m19,m20,m21,m22,m23,m24,m25,m26,m27,m28,m29,m30] = t;
        f(m0);f(m1);f(m2);f(m3);f(m4);f(m5);f(m6);f(m7);f(m8);f(m9);f(m10);f(m11);f(m12);f(m13);f(m14);f(m15);f(m16);f(m17);f(m18);f(m19);f(m20);f(m21);f(m22);f(m23);f(m24);f(m25);f(m26);f(m27);f(m28);f(m29);f(m30);
    } else if constexpr (n == 32) {
        auto &[m0,m1,m2,m3,m4,m5,m6,m7,m8,m9,m10,m11,m12,m13,m14,m15,m16,m17,m18,m19,m20,m21,m22,m23,m24,m25,m26,m27,m28,m29,m30,m31] = t;
        f(m0);f(m1);f(m2);f(m3);f(m4);f(m5);f(m6);f(m7);f(m8);f(m9);f(m10);f(m11);f(m12);f(m13);f(m14);f(m15);f(m16);f(m17);f(m18);f(m19);f(m20);f(m21);f(m22);f(m23);f(m24);f(m25);f(m26);f(m27);f(m28);f(m29);f(m30);f(m31);
    } else {
        return false;  // more members than it knows: the caller reports it
    }
    return true;
    // clang-format on
}

/// The byte ranges of the members a field list visits: pass it to VisitFields.
struct VisitedBytes {
    std::vector<std::pair<const char *, const char *>> ranges;

    template <typename T>
    void operator()(const char *, T &member, const char *) {
        Add(member);
    }
    template <typename T, typename Extra>
    void operator()(const char *, T &member, const Extra &, const char *) {
        Add(member);
    }
    template <typename T>
    void Add(T &member) {
        const char *begin = reinterpret_cast<const char *>(&member);
        ranges.emplace_back(begin, begin + sizeof(T));
    }
    [[nodiscard]] bool Touches(const char *begin, const char *end) const {
        for (const auto &[b, e] : ranges)
            if (b < end && begin < e) return true;
        return false;
    }
};

/// The members of @p config (recursively: of its struct members) that hold no field the list
/// visited, as "Type member #k"; @p exempt are the addresses of members that are no field.
template <typename T>
void UnvisitedMembers(T &config, const VisitedBytes &visited,
                      const std::vector<const void *> &exempt, std::vector<std::string> &missing) {
    std::size_t index = 0;
    const bool known = ForEachMember(config, [&](auto &member) {
        using M = std::decay_t<decltype(member)>;
        const char *begin = reinterpret_cast<const char *>(&member);
        bool skip = false;
        for (const void *address : exempt) skip |= address == static_cast<const void *>(&member);
        if (!skip && !visited.Touches(begin, begin + sizeof(M))) {
            missing.push_back(std::string(typeid(T).name()) + " member #" + std::to_string(index));
        } else if constexpr (std::is_class_v<M> && std::is_aggregate_v<M>) {
            if (!skip) UnvisitedMembers(member, visited, exempt, missing);
        }
        ++index;
    });
    if (!known) missing.push_back(std::string(typeid(T).name()) + ": too many members to check");
}

/// UnvisitedMembers of a config whose field list is VisitFields(config, visitor).
template <typename T>
[[nodiscard]] std::vector<std::string> MembersWithoutField(
    T &config, const std::vector<const void *> &exempt) {
    VisitedBytes visited;
    VisitFields(config, visited);
    std::vector<std::string> missing;
    UnvisitedMembers(config, visited, exempt, missing);
    return missing;
}

}  // namespace dorado::testing
